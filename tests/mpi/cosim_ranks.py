"""fe_server on 1, 2 and 3 MPI ranks against one: standalone, the
axisymmetric bar impact (scenes/bar_impact_axi) with LS-DYNA ASCII files
(glstat, matsum: every node's velocity, gathered at rank 0) and field
snapshots; co-simulated, the elastic hammer (scenes/hammer_elastic: its
dynamic relaxation, contacts, rigid bodies, cavity ports in TLM mode). The
histories, fields, ASCII files and the host's results must match the
one-rank runs; then a rank killed mid-run must stop the host within its
deadline with a message, and rank 0's history must stay readable.

usage: cosim_ranks.py MPIEXEC FE_SERVER TLM_HOST SCENE_DIR BUILD_SCENE_DIR [--sanitized]

--sanitized (the AddressSanitizer build, where each relaxation takes a
minute): 2 ranks only, and no SIGTERM case; the memory checks are what
that build is for.

Tolerances: the runs differ in the order of the sums at shared nodes only
(tests/mpi/test_ranks.cpp); over the ~130000 FE steps here (the relaxation
and 4 ms of hammering) such round-off stays below 1e-9 of each FE series'
largest value (measured: up to 1.3e-12 on 3 ranks). The energy balance
error is itself a difference of large energies: it is compared with the
energy scale, not with its own size. The host's series get 1e-6: an
orifice's flow goes as the square root of its pressure drop, which
amplifies a relative perturbation of the cavity pressures by (scale / 2Δp)
where the drop passes through zero (measured: up to 5.3e-9, an orifice's
integrated loss, on 3 ranks; 0 on 2).
"""
import os
import signal
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

mpiexec = sys.argv[1]
fe_server, tlm_host, scene, build_scene = (os.path.abspath(a) for a in sys.argv[2:6])
SANITIZED = "--sanitized" in sys.argv[6:]
RANKS = (2,) if SANITIZED else (1, 2, 3)
TOL_FE, TOL_HOST = 1e-9, 1e-6
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


def env():
    e = dict(os.environ)
    e.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1",
             PCS_TOKEN="mpi-test-token-0123456789")
    return e


def start_server(ranks, tmp, tag):
    port_file = os.path.join(tmp, f"port_{tag}")
    cmd = [fe_server, "--model", os.path.join(build_scene, "deck.k"), "--ports", os.path.join(scene, "ports.cfg"),
           "--listen", "127.0.0.1:0", "--port-file", port_file, "--out", os.path.join(tmp, tag, f"fe_{tag}.h5"),
           "--accept-timeout", "120"]
    if ranks > 0:
        cmd = [mpiexec, "-n", str(ranks)] + cmd
    os.makedirs(os.path.join(tmp, tag), exist_ok=True)  # its own folder: the LS-DYNA ASCII files go beside the results
    log = open(os.path.join(tmp, f"fe_{tag}.log"), "w")
    server = subprocess.Popen(cmd, env=env(), stdout=log, stderr=subprocess.STDOUT)
    # The port is written at bind, the relaxation comes after it: the host
    # starts once fe_server listens with the settled model (on 3 ranks
    # sharing 2 cores the relaxation can outlast the host's handshake wait).
    deadline = time.time() + 300
    log_path = os.path.join(tmp, f"fe_{tag}.log")
    while time.time() < deadline:
        if os.path.exists(port_file) and "listening on" in open(log_path).read():
            return server, open(port_file).read().strip()
        if server.poll() is not None:
            break
        time.sleep(0.1)
    server.kill()
    print(open(os.path.join(tmp, f"fe_{tag}.log")).read())
    sys.exit(f"fe_server ({tag}) did not start")


def host_model(tmp):
    """The scene's host model without its *REPORT block (a report needs blows
    after 0.3 s; these runs are 4 ms)."""
    lines, out, skip = open(os.path.join(scene, "model.tlm")).read().splitlines(), [], False
    for line in lines:
        if line.startswith("*"):
            skip = line.strip().upper() == "*REPORT"
        if not skip:
            out.append(line)
    path = os.path.join(tmp, "model.tlm")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return path


def start_host(port, tmp, tag, stop):
    return subprocess.Popen([tlm_host, host_model(tmp), "--fmu",
                             os.path.join(build_scene, "hammer_elastic.fmu"), "--server", f"127.0.0.1:{port}", "--out",
                             os.path.join(tmp, f"host_{tag}.h5"), "--set", f"simulation.stoptime={stop}", "--set",
                             "simulation.timestep=1e-5", "--quiet"],
                            env=env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def series(path):
    out = {}
    with h5py.File(path, "r", swmr=True) as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f":
                out[name] = np.asarray(obj)
        f.visititems(visit)
    return out


def compare(a, b, what, tol):
    sa, sb = series(a), series(b)
    check(sa.keys() == sb.keys() and len(sa) > 0, f"{what}: the same {len(sa)} series")
    energy_scale = max([np.max(np.abs(v)) for k, v in sa.items() if k.startswith("energy/")] or [1.0])
    worst, where = 0.0, ""
    for k in sa:
        if k not in sb or sa[k].shape != sb[k].shape:
            check(False, f"{what}: {k} has another shape")
            continue
        scale = energy_scale if k == "energy/balance_error" else np.max(np.abs(sa[k])) if sa[k].size else 0.0
        d = np.max(np.abs(sa[k] - sb[k])) / scale if scale > 0 else 0.0
        if d > worst:
            worst, where = d, k
    check(worst < tol, f"{what}: largest difference {worst:.3g} of its series' scale ({where or 'none'})")


def ascii_same(a, b):
    if not (os.path.exists(a) and os.path.exists(b)):
        return False
    def tokens(path):
        return [ln.split() for ln in open(path) if "zone cycle" not in ln and "date" not in ln]
    ta, tb = tokens(a), tokens(b)
    def number(t):
        try:
            return float(t)
        except ValueError:
            return None
    scale = max([abs(number(t)) for ln in ta for t in ln if number(t) is not None] or [1.0])
    if len(ta) != len(tb):
        return False
    for la, lb in zip(ta, tb):
        if len(la) != len(lb):
            return False
        for x, y in zip(la, lb):
            nx, ny = number(x), number(y)
            if nx is None or ny is None:
                if x != y:
                    return False
            elif abs(nx - ny) > 2e-5 * max(abs(nx), abs(ny)) + 1e-9 * scale:
                return False
    return True


def session(ranks, tmp, tag, stop="0.004"):
    server, port = start_server(ranks, tmp, tag)
    host = start_host(port, tmp, tag, stop)
    out, _ = host.communicate(timeout=600)
    try:
        rc = server.wait(timeout=120)
    except subprocess.TimeoutExpired:
        server.kill()
        rc = "none (killed after 120 s)"
        print(out[-2000:], open(os.path.join(tmp, f"fe_{tag}.log")).read()[-2000:])
    check(host.returncode == 0 and rc == 0, f"{tag}: host exit {host.returncode}, fe_server exit {rc}" +
          ("" if host.returncode == 0 else ": " + out[-400:]))


def rank_pid(server, rank):
    """The process of `rank` among mpirun's children (its environment says which)."""
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/stat") as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
            if ppid != server.pid:
                continue
            with open(f"/proc/{pid}/environ", "rb") as f:
                if f"OMPI_COMM_WORLD_RANK={rank}\0".encode() in f.read():
                    return int(pid)
        except (OSError, ValueError, IndexError):
            pass
    return None


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime + stime


def into_a_session(tmp, tag, idle_check=False):
    """fe_server on 2 ranks and a host of a long run, 2 s into the session
    (the relaxation comes before it, rows only after). idle_check: first,
    with no host yet, rank 1 waiting for rank 0's word must not spin (a
    spinning rank burns the whole 2 s; with naps of a fixed 20 µs it used
    0.44 s, with the naps growing to 1 ms 0.04 s; the bound leaves room for
    a loaded machine)."""
    server, port = start_server(2, tmp, tag)
    if idle_check:
        rank1 = rank_pid(server, 1)
        if rank1 is not None:
            before = cpu_seconds(rank1)
            time.sleep(2.0)
            used = cpu_seconds(rank1) - before
            check(used < 0.2, f"rank 1 waiting for the host used {used:.2f} s of CPU in 2 s")
    host = start_host(port, tmp, tag, "0.1")
    deadline = time.time() + 120
    while time.time() < deadline and "session accepted" not in open(os.path.join(tmp, f"fe_{tag}.log")).read():
        time.sleep(0.1)
    time.sleep(2.0)
    return server, host


def standalone(ranks, tmp, tag):
    """The bar impact run by fe_server alone, in its own folder."""
    d = os.path.join(tmp, tag)
    os.makedirs(d, exist_ok=True)
    deck = os.path.join(tmp, "impact.k")
    with open(deck, "w") as f:  # the scene's deck with ASCII output every 2 µs
        f.write("*KEYWORD\n*DATABASE_GLSTAT\n2e-6\n*DATABASE_MATSUM\n2e-6\n*INCLUDE\n" +
                os.path.join(os.path.dirname(build_scene), "bar_impact_axi", "deck.k") + "\n*END\n")
    cmd = [fe_server, "--model", deck, "--out", os.path.join(d, "fe.h5"), "--quiet"]
    if ranks > 0:
        cmd = [mpiexec, "-n", str(ranks)] + cmd
    r = subprocess.run(cmd, env=env(), capture_output=True, text=True, timeout=300)
    check(r.returncode == 0, f"standalone {tag}: exit {r.returncode} {r.stdout[-300:]}")
    return d


with tempfile.TemporaryDirectory() as tmp:
    one = standalone(0, tmp, "alone_serial")
    for ranks in [r for r in RANKS if r > 1]:
        many = standalone(ranks, tmp, f"alone_ranks{ranks}")
        compare(os.path.join(one, "fe.h5"), os.path.join(many, "fe.h5"), f"standalone, {ranks} ranks: history", TOL_FE)
        compare(os.path.join(one, "fe_fields.h5"), os.path.join(many, "fe_fields.h5"),
                f"standalone, {ranks} ranks: field snapshots", TOL_FE)
        for name in ("glstat", "matsum"):
            check(ascii_same(os.path.join(one, name), os.path.join(many, name)),
                  f"standalone, {ranks} ranks: {name} as on one rank")
    session(0, tmp, "serial")
    for ranks in RANKS:
        tag = f"ranks{ranks}"
        session(ranks, tmp, tag)
        compare(os.path.join(tmp, "host_serial.h5"), os.path.join(tmp, f"host_{tag}.h5"), f"{tag}: tlm_host's results", TOL_HOST)
        compare(os.path.join(tmp, "serial", "fe_serial.h5"), os.path.join(tmp, tag, f"fe_{tag}.h5"),
                f"{tag}: fe_server's histories", TOL_FE)
        # glstat reads every node's velocity (gathered at rank 0): the same
        # text but for the wall-time line, each number within its last
        # printed digit (5 significant: 2e-5) or round-off of the file's
        # largest number (a momentum that is zero but for round-off).
        for name in ("glstat", "nodout"):
            check(ascii_same(os.path.join(tmp, "serial", name), os.path.join(tmp, tag, name)),
                  f"{tag}: the deck's LS-DYNA ASCII file {name} as on one rank")
        # The deck's ELOUT serves its cross sections (HDF5); elout lists
        # history solids, of which it has none: not written, on any rank.
        check(not os.path.exists(os.path.join(tmp, tag, "elout")), f"{tag}: no elout without history solids")
    log = open(os.path.join(tmp, "fe_ranks2.log")).read()
    check("2 ranks (METIS" in log, "fe_server said how it partitioned the model")

    # A rank killed mid-run (a node of the cluster lost): mpirun ends the
    # others, the host's link closes and it stops with a message, well within
    # its 60 s step deadline (ports.cfg); rank 0's history is readable (SWMR).
    server, host = into_a_session(tmp, "killed", idle_check=True)
    rank1 = rank_pid(server, 1)
    check(rank1 is not None, "found rank 1's process")
    if rank1 is not None:
        t0 = time.time()
        os.kill(rank1, signal.SIGKILL)
        try:
            out, _ = host.communicate(timeout=90)
        except subprocess.TimeoutExpired:
            host.kill()
            out, _ = host.communicate()
        took = time.time() - t0
        check(host.returncode not in (0, None) and took < 60.0,
              f"the host stopped {took:.1f} s after the kill, exit {host.returncode}")
        check("closed" in out or "lost" in out or "ABORT" in out or "abort" in out, "the host said why: " + out.strip()[-200:])
        try:
            server.wait(timeout=60)
        except subprocess.TimeoutExpired:
            server.kill()
            check(False, "mpirun ended after the rank was killed")
        rows = series(os.path.join(tmp, "killed", "fe_killed.h5")).get("time", np.zeros(0))
        check(rows.size > 0 and np.all(np.diff(rows) > 0), f"rank 0's history readable: {rows.size} rows")
    else:
        server.kill()
        host.kill()

    # SIGTERM to mpirun mid-run (SLURM at the wall-time limit, Ctrl-C): it
    # passes the signal to every rank; rank 0 tells the host why and closes
    # its history (readable without SWMR), the others end with it.
    if SANITIZED:
        sys.exit(1 if failures else 0)
    server, host = into_a_session(tmp, "signal")
    server.send_signal(signal.SIGTERM)
    try:
        out, _ = host.communicate(timeout=60)
        server.wait(timeout=60)
    except subprocess.TimeoutExpired:
        host.kill()
        server.kill()
        out = "time-out"
    check("stopped by SIGTERM" in out, "the host was told of the signal: " + out.strip()[-200:])
    with h5py.File(os.path.join(tmp, "signal", "fe_signal.h5"), "r") as f:
        check(f["time"].shape[0] > 0, f"rank 0's history closed with {f['time'].shape[0]} rows")

if failures:
    sys.exit(1)
