#!/usr/bin/env python3
"""Writes the seed corpus of the fmu_unpack fuzz target (corpus/fmu_unpack/):
.fmu archives a hostile or broken file would be, each a case the importer
must refuse (or load) and leave no folder behind. Run it again after changing
a case; the files are committed so that the replay needs no Python.
"""
import io
import os
import stat
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "corpus", "fmu_unpack")

MD = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="seed" guid="pcs-0000000000000000"
  generationTool="corpus" variableNamingConvention="structured" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="{ident}" needsExecutionTool="true"/>
  <ModelVariables>
    <ScalarVariable name="server.host" valueReference="1" causality="parameter" variability="fixed">
      <String start=""/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure/>
</fmiModelDescription>
"""


def archive(entries, compression=zipfile.ZIP_DEFLATED):
    """entries: (name, bytes[, unix mode]) in order."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression) as z:
        for e in entries:
            info = zipfile.ZipInfo(e[0])
            info.compress_type = compression
            if len(e) > 2:
                info.external_attr = e[2] << 16
            z.writestr(info, e[1])
    return buf.getvalue()


def md(ident="seed"):
    return ("modelDescription.xml", MD.format(ident=ident).encode())


CASES = {
    # A description whose binary is missing: refused at dlopen.
    "no_binary.fmu": archive([md()]),
    # A "binary" that is text: dlopen refuses it.
    "text_binary.fmu": archive([md(), ("binaries/linux64/seed.so", b"not an ELF file\n")]),
    # Entries that leave the folder (zip slip), by .. and by an absolute path.
    "zip_slip.fmu": archive([md(), ("../escaped.txt", b"outside\n")]),
    "absolute_entry.fmu": archive([md(), ("/tmp/pcs_absolute_entry.txt", b"outside\n")]),
    "nested_slip.fmu": archive([md(), ("resources/../../escaped.txt", b"outside\n")]),
    # A symbolic link entry pointing out of the folder.
    "symlink.fmu": archive([md(), ("resources/link", b"/etc/passwd", stat.S_IFLNK | 0o777)]),
    # 8 MB of zeros in a few KB: past the 1 MB unpack limit the fuzz target sets.
    "bomb.fmu": archive([md(), ("resources/zeros.bin", bytes(8 << 20))]),
    # A modelIdentifier that is a path, not a C identifier.
    "identifier_path.fmu": archive([md("../../tmp/evil"), ("binaries/linux64/seed.so", b"x")]),
    # No modelDescription.xml at all; a broken one.
    "no_description.fmu": archive([("resources/ports.cfg", b"$FMU_MODEL\none_dof\n")]),
    "broken_description.fmu": archive([("modelDescription.xml", b"<fmiModelDescription fmiVersion=\"2.0\"")]),
    # The same entry twice.
    "duplicate_entries.fmu": archive([md(), md("other")], zipfile.ZIP_STORED),
    # Many tiny entries.
    "many_entries.fmu": archive([md()] + [("resources/f%05d" % i, b"") for i in range(1000)], zipfile.ZIP_STORED),
    # Not a zip; an empty file; a zip cut in half.
    "not_a_zip.fmu": b"PK this is not a zip archive\n",
    "empty.fmu": b"",
}
CASES["truncated.fmu"] = CASES["text_binary.fmu"][: len(CASES["text_binary.fmu"]) // 2]


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, data in sorted(CASES.items()):
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
        print("%-26s %8d bytes" % (name, len(data)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
