#!/usr/bin/env python3
"""The FMU's win64 DLL (issue 38).

exports: the DLL in the FMU exports every FMI 2.0 and FMI 3.0 function
  (fmu/include/fmi2/fmi2.h and fmi3/fmi3.h list them) and pcs_fmu_*,
  nothing else, and imports only Windows' own DLLs. Needs MinGW-w64's
  objdump (skipped without it).
wine: our small FMI 2.0 importer, cross-compiled for Windows, runs the DLL
  under Wine against a Linux fe_server on loopback; the Linux build of the
  same importer runs the FMU's .so against another; the outputs of every
  step are the same digits. Skipped without Wine.

usage: win64_test.py exports FMU
       win64_test.py wine FMU FE_SERVER SCENE_DIR WINDOWS_DRIVER LINUX_DRIVER
"""
import os
import re
import secrets
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "support"))
from fe_server_process import start_fe_server  # noqa: E402

SKIP = 77
ROOT = Path(__file__).resolve().parents[2]
SYSTEM_DLLS = {"kernel32.dll", "msvcrt.dll", "ws2_32.dll", "bcrypt.dll"}
STEPS = 200


def listed_functions(header, macro):
    """The names in a header's X-list macro (PCS_FMI2_FUNCTIONS, ...)."""
    text = (ROOT / header).read_text()
    body = text[text.index(f"#define {macro}(X)"):]
    body = body[:body.index("\n\n")] if "\n\n" in body else body
    return set(re.findall(r"X\((fmi[23]\w+)\)", body))


def unpack(fmu, d):
    with zipfile.ZipFile(fmu) as z:
        z.extractall(d)
    md = ET.parse(Path(d) / "modelDescription.xml").getroot()
    ident = md.find("CoSimulation").get("modelIdentifier")
    return md, ident


def exports(fmu):
    objdump = shutil.which("x86_64-w64-mingw32-objdump")
    if not objdump:
        print("skipped: x86_64-w64-mingw32-objdump not found (Debian: binutils-mingw-w64-x86-64)")
        return SKIP
    failures = []
    with tempfile.TemporaryDirectory() as d:
        md, ident = unpack(fmu, d)
        dll = Path(d) / "binaries" / "win64" / f"{ident}.dll"
        if not dll.exists():
            print(f"FAIL: {fmu} has no binaries/win64/{ident}.dll")
            return 1
        text = subprocess.run([objdump, "-p", str(dll)], capture_output=True, text=True, check=True).stdout
        table = text[text.index("[Ordinal/Name Pointer] Table"):].split("\n\n")[0]
        exported = set(re.findall(r"^\s*\[\s*\d+\]\s+(\w+)", table, re.M))
        imports = {m.lower() for m in re.findall(r"DLL Name: (\S+)", text)}
    want = listed_functions("fmu/include/fmi2/fmi2.h", "PCS_FMI2_FUNCTIONS") | \
        listed_functions("fmu/include/fmi3/fmi3.h", "PCS_FMI3_FUNCTIONS")
    if len(want) < 34 + 60:
        failures.append(f"read only {len(want)} function names from the headers")
    missing = sorted(want - exported)
    if missing:
        failures.append(f"not exported: {missing}")
    extra = sorted(n for n in exported - want if not n.startswith("pcs_fmu_"))
    if extra:
        failures.append(f"exported beyond FMI and pcs_fmu_*: {extra[:20]}")
    if not imports <= SYSTEM_DLLS:
        failures.append(f"imports beyond Windows' own DLLs: {sorted(imports - SYSTEM_DLLS)}")
    fmi2 = sum(1 for n in exported if n.startswith("fmi2"))
    print(f"{ident}.dll exports {len(exported)} functions ({fmi2} FMI 2.0, "
          f"{sum(1 for n in exported if n.startswith('fmi3'))} FMI 3.0), imports {sorted(imports)}")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


def run_driver(cmd, env, what):
    run = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=240)
    lines = [l.rstrip("\r") for l in run.stdout.splitlines() if l.strip()]
    return run, lines


def wine(fmu, fe_server, scene, windows_driver, linux_driver):
    wine_exe = shutil.which("wine") or shutil.which("wine64")
    if not wine_exe:
        print("skipped: wine not found (Debian: wine64; scripts/install_deps.sh installs it)")
        return SKIP
    env = {**os.environ, "PCS_TOKEN": secrets.token_hex(16), "WINEDEBUG": "-all"}
    failures = []
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        md, ident = unpack(fmu, d / "fmu")
        guid = md.get("guid")
        # cavity.p (vr 0) held at 3 MPa; cavity.q and cavity.x (vr 1, 2) out.
        args = [guid, "127.0.0.1", None, str(STEPS), "1e-05", "0", "3e6", "1,2"]
        outputs = {}
        for tag, driver in (("win64", windows_driver), ("linux64", linux_driver)):
            server, _ = start_fe_server(fe_server, scene / "piston.k", scene / "ports.cfg", d / f"port_{tag}",
                                        ["--out", str(d / f"fe_{tag}.h5")], env)
            port = (d / f"port_{tag}").read_text().strip() if (d / f"port_{tag}").exists() else "0"
            a = list(args)
            a[2] = port
            try:
                if tag == "win64":
                    # Wine sees the Linux root as drive Z:.
                    lib = "Z:" + str(d / "fmu" / "binaries" / "win64" / f"{ident}.dll").replace("/", "\\")
                    uri = "file:///Z:" + str(d / "fmu" / "resources")
                    cmd = [wine_exe, str(windows_driver), lib, uri] + a
                else:
                    cmd = [str(linux_driver), str(d / "fmu" / "binaries" / "linux64" / f"{ident}.so"),
                           "file://" + str(d / "fmu" / "resources")] + a
                run, lines = run_driver(cmd, env, tag)
                code = server.wait(timeout=60)
            finally:
                if server.poll() is None:
                    server.kill()
            if run.returncode != 0 or code != 0 or len(lines) != STEPS:
                failures.append(f"{tag}: importer exit {run.returncode}, fe_server exit {code}, {len(lines)} of "
                                f"{STEPS} steps\n{run.stderr[-3000:]}\n{server.stdout.read()[-2000:]}")
            outputs[tag] = lines
        if not failures:
            differ = [i + 1 for i, (a, b) in enumerate(zip(outputs["win64"], outputs["linux64"])) if a != b]
            if differ:
                failures.append(f"the win64 DLL's outputs differ from the .so's at {len(differ)} steps, first "
                                f"{differ[0]}: {outputs['win64'][differ[0] - 1]} vs {outputs['linux64'][differ[0] - 1]}")
            else:
                print(f"win64 DLL under Wine against fe_server: {STEPS} steps, the same digits as the .so's "
                      f"(last: {outputs['win64'][-1]})")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


def main():
    if len(sys.argv) >= 3 and sys.argv[1] == "exports":
        return exports(sys.argv[2])
    if len(sys.argv) == 7 and sys.argv[1] == "wine":
        return wine(sys.argv[2], sys.argv[3], Path(sys.argv[4]), sys.argv[5], sys.argv[6])
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main())
