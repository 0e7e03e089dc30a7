#!/usr/bin/env python3
"""The FMU as it goes to another machine (issue 38): what its binary needs
from the system, and how the archive is packed.

- Its .so needs nothing newer than GLIBC_2.28 (RHEL 8, Ubuntu 20.04, Debian
  10 and newer): every version objdump -T lists is at most 2.28, and none of
  libstdc++'s or libgcc's (GLIBCXX_, CXXABI_, GCC_), which are linked in.
- It needs no library but libc, libm and the loader.
- It carries no debug info and no path of this build.
- Every zip entry is mode 0644.
- documentation/index.html names every variable of modelDescription.xml with
  its unit; documentation/licenses/ holds libsodium's and the GCC runtime's.
- The numbers in modelDescription.xml are the shortest that read back exactly.

usage: portable_binary.py FMU BUILD_PATH
"""
import re
import shutil
import stat
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile

MAX_GLIBC = (2, 28)
ALLOWED_NEEDED = {"libc.so.6", "libm.so.6", "ld-linux-x86-64.so.2"}


def version_tuple(text):
    return tuple(int(x) for x in text.split("."))


def main():
    fmu, build_path = sys.argv[1], sys.argv[2]
    failures = []
    for tool in ("objdump", "readelf"):
        if not shutil.which(tool):
            print(f"skipped: {tool} not found (Debian: binutils)")
            return 77
    with zipfile.ZipFile(fmu) as z:
        names = z.namelist()
        for info in z.infolist():
            mode = (info.external_attr >> 16) & 0o7777
            if mode != 0o644:
                failures.append(f"{info.filename}: mode {oct(mode)}, want 0o644")
            if not stat.S_ISREG(info.external_attr >> 16):
                failures.append(f"{info.filename}: not stored as a regular file")
        md = ET.fromstring(z.read("modelDescription.xml"))
        ident = md.find("CoSimulation").get("modelIdentifier")
        fmi3 = md.get("fmiVersion") == "3.0"
        so_name = f"binaries/{'x86_64-linux' if fmi3 else 'linux64'}/{ident}.so"
        # (name, unit, start) of every variable, in either version's layout.
        if fmi3:
            variables = [(v.get("name"), v.get("unit"), v.get("start") if v.tag == "Float64" else None)
                         for v in md.find("ModelVariables")]
        else:
            variables = [(v.get("name"), (v.find("Real").get("unit") if v.find("Real") is not None else None),
                          (v.find("Real").get("start") if v.find("Real") is not None else None))
                         for v in md.iter("ScalarVariable")]
        if so_name not in names:
            print(f"FAIL: {so_name} not in {fmu}")
            return 1
        import tempfile
        with tempfile.TemporaryDirectory() as d:
            so = z.extract(so_name, d)
            dyn = subprocess.run(["objdump", "-T", so], capture_output=True, text=True, check=True).stdout
            glibc = sorted({version_tuple(v) for v in re.findall(r"\(GLIBC_([0-9.]+)\)", dyn)})
            too_new = [v for v in glibc if v > MAX_GLIBC]
            if too_new:
                syms = [l.split()[-1] + " " + l.split()[-2] for l in dyn.splitlines()
                        if any(f"GLIBC_{'.'.join(map(str, v))})" in l for v in too_new)]
                failures.append(f"needs glibc newer than 2.28: {syms}")
            for family in ("GLIBCXX_", "CXXABI_", "GCC_"):
                if family in dyn:
                    failures.append(f"needs {family}* from a shared library (it should be linked in statically)")
            dynamic = subprocess.run(["readelf", "-d", so], capture_output=True, text=True, check=True).stdout
            needed = set(re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", dynamic))
            if not needed <= ALLOWED_NEEDED:
                failures.append(f"needs libraries beyond libc/libm: {sorted(needed - ALLOWED_NEEDED)}")
            sections = subprocess.run(["readelf", "-S", "-W", so], capture_output=True, text=True, check=True).stdout
            debug = sorted(set(re.findall(r"\.debug_\w+", sections)))
            if debug:
                failures.append(f"carries debug info: {debug}")
            data = open(so, "rb").read()
            if build_path.encode() in data:
                failures.append(f"carries this build's path {build_path}")
            print(f"{so_name}: {len(data)} bytes, glibc versions up to "
                  f"{'.'.join(map(str, glibc[-1])) if glibc else '-'}, needs {sorted(needed)}")
        # The documentation.
        if "documentation/index.html" not in names:
            failures.append("no documentation/index.html")
        else:
            html = z.read("documentation/index.html").decode()
            for name, unit, _ in variables:
                if name == "time" and fmi3:
                    continue  # the independent variable
                if f"<code>{name}</code>" not in html:
                    failures.append(f"documentation/index.html does not list {name}")
                if unit and f"<td>{unit}</td>" not in html:
                    failures.append(f"documentation/index.html lacks the unit {unit} of {name}")
            for needed_text in ("server.token", "PCS_TOKEN", "fe_server"):
                if needed_text not in html:
                    failures.append(f"documentation/index.html does not say how to use {needed_text}")
        licences = [n for n in names if n.startswith("documentation/licenses/")]
        for want in ("libsodium", "gcc-runtime"):
            if not any(want in n for n in licences):
                failures.append(f"no licence text for {want} in documentation/licenses/ ({licences})")
        # Shortest round-trip numbers (Python's repr is the shortest too).
        numbers = [(k, md.find("DefaultExperiment").get(k)) for k in ("stepSize", "stopTime")]
        numbers += [(name, start) for name, _, start in variables if start]
        for what, text in numbers:
            if repr(float(text)) != text and repr(float(text)) != text + ".0":
                failures.append(f"{what}='{text}' is not the shortest form ({repr(float(text))})")
        for attr in ("generationTool", "generationDateAndTime", "version", "description"):
            if not md.get(attr):
                failures.append(f"modelDescription.xml has no {attr}")
    for f in failures:
        print("FAIL:", f)
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
