#!/usr/bin/env python3
"""The gmsh path end to end: gmsh meshes tool.geo (tetrahedra), fe_mesh
--from-gmsh makes the keyword mesh, and fe_server runs a deck that includes
it, a pressure step in the bore, standalone. Checks: every step exits 0,
the mesh is tetrahedral with the three named surfaces, and the run's energy
account closes (external work = kinetic + internal + what the bulk
viscosity took, within 1 %, the bound fe_server itself stops at). Exit 77
(skipped) without gmsh.

usage: end_to_end.py FE_MESH FE_SERVER"""
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    fe_mesh, fe_server = sys.argv[1], sys.argv[2]
    gmsh = shutil.which("gmsh")
    if not gmsh:
        print("gmsh is not installed (scripts/install_deps.sh installs it): skipped")
        return 77
    with tempfile.TemporaryDirectory() as d:
        msh, mesh, deck, out = (os.path.join(d, n) for n in ("tool.msh", "tool.k", "run.k", "run.h5"))
        subprocess.run([gmsh, "-3", os.path.join(HERE, "tool.geo"), "-format", "msh41", "-o", msh],
                       check=True, stdout=subprocess.DEVNULL, timeout=120)
        r = subprocess.run([fe_mesh, "--from-gmsh", msh, "-o", mesh], check=True, capture_output=True, text=True,
                           timeout=60)
        print(r.stdout, end="")
        for want in ("tetrahedra (ELFORM 10)", "'top'", "'bottom'", "'bore'"):
            assert want in r.stdout, f"fe_mesh's summary lacks {want!r}"
        with open(deck, "w") as f:
            f.write("*KEYWORD\n*INCLUDE\ntool.k\n*MAT_ELASTIC\n1,7850,2e11,0.3\n"
                    "*DEFINE_CURVE\n1\n0,1\n1,1\n*LOAD_SEGMENT_SET\n13,1,1e7\n"
                    "*CONTROL_TERMINATION\n1e-4\n*END\n")
        subprocess.run([fe_server, "--model", deck, "--out", out, "--quiet"], check=True, timeout=600, cwd=d)
        with h5py.File(out) as h:
            e = {k: np.asarray(h["energy"][k]) for k in h["energy"]}
        work = e["external_work"][-1]
        held = e["kinetic"][-1] + e["internal"][-1] + e["damping"][-1] + e["hourglass"][-1]
        print(f"external work {work:.4g} J, kinetic + internal + damping {held:.4g} J")
        assert work > 0.0, "the pressure did no work"
        assert abs(work - held) < 0.01 * work, "the energy account does not close"
    return 0


if __name__ == "__main__":
    sys.exit(main())
