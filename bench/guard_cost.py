"""The cost of the run-quality guards (issue 32): the FE element cycle and the
TLM host step, this build against the revision before the guards, built in
a temporary folder outside the repository, in interleaved pairs.

FE (bench_fe axi4 and hex8, ns per element-cycle, the fastest slice of each
run): the per-element current stable step (one multiply per lane and a
batch min), the bounding-box check every 32 steps and the non-finite check
at every step's energy sum. TLM host (bench_tlm, ns per component-step on
the monolithic hammer): the node check every 16 steps and the check of every
results row.

Run: /usr/bin/python3 bench/guard_cost.py [--pairs N] [--before REV]
(writes bench/results/guard_cost.json, which bench/run_benchmarks.py puts
into bench/RESULTS.md).
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BEFORE = "ceee863"  # the last revision without the guards


def build_before(rev, work):
    src = Path(work) / "src"
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(src), rev], check=True,
                   capture_output=True)
    build = Path(work) / "build"
    subprocess.run(["cmake", "-S", str(src), "-B", str(build), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=RelWithDebInfo"],
                   check=True, capture_output=True)
    subprocess.run(["cmake", "--build", str(build), "--target", "bench_fe", "bench_tlm"], check=True,
                   capture_output=True)
    return build / "bench", src


def fe_costs(bench):
    out = subprocess.run([str(bench / "bench_fe"), "axi4", "hex8"], capture_output=True, text=True, check=True).stdout
    return {f"{m[0]} {m[1]}": float(m[2]) for m in re.findall(r"csv:fe_cost,(\w+),(\d+),([0-9.]+)", out)}


def tlm_cost(bench):
    out = subprocess.run([str(bench / "bench_tlm"), "1.0"], capture_output=True, text=True, check=True).stdout
    return float(re.search(r"csv:tlm_cost,\d+,([0-9.]+)", out).group(1))


# The guards' own functions, by the name perf reports (not inlined: each is
# out of the hot loops by design). Their share of one run's samples is a
# cost measured within one run, which the machine's noise between runs does
# not blur; the per-element limit (one multiply in the kernel) and the batch
# minimum are inside the kernels and not separable this way.
GUARD_FUNCTIONS = {
    "fe": ["fe::Solver::check_state", "fe::Solver::energy_account", "fe::Solver::first_non_finite"],
    "tlm": ["tlm::System::check_nodes", "tlm::System::check_fmu_nodes", "tlm::System::node_failure"],
}


def attribution(cmd, functions):
    """Share [%] of the samples of `cmd` in each guard function (perf
    record), or None without perf."""
    if shutil.which("perf") is None:
        return None
    with tempfile.TemporaryDirectory(prefix="pcs_perf_") as d:
        data = Path(d) / "perf.data"
        rec = subprocess.run(["perf", "record", "-q", "-o", str(data), *cmd], capture_output=True, text=True)
        if rec.returncode != 0:
            return None
        rep = subprocess.run(["perf", "report", "-i", str(data), "--no-children", "--percent-limit", "0",
                              "--stdio"], capture_output=True, text=True).stdout
    shares = {}
    for f in functions:
        shares[f] = sum(float(m) for m in re.findall(r"^\s+([0-9.]+)%.*\] " + re.escape(f) + r"\b", rep, re.M))
    return shares


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pairs", type=int, default=8)
    ap.add_argument("--before", default=BEFORE)
    a = ap.parse_args()
    now = Path(os.environ.get("PCS_BUILD_DIR", ROOT / "build")) / "bench"
    with tempfile.TemporaryDirectory(prefix="pcs_guard_") as work:
        before, src = build_before(a.before, work)
        try:
            runs = {"before": [], "after": []}
            for _ in range(a.pairs):
                for tag, bench in (("before", before), ("after", now)):
                    r = fe_costs(bench)
                    r["tlm host"] = tlm_cost(bench)
                    runs[tag].append(r)
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(src)], capture_output=True)
    rows = []
    for key in runs["after"][0]:
        b = [r[key] for r in runs["before"]]
        f = [r[key] for r in runs["after"]]
        rows.append({"case": key, "before_min": min(b), "after_min": min(f), "before_median": statistics.median(b),
                     "after_median": statistics.median(f), "ratio_min": min(f) / min(b),
                     "ratio_median": statistics.median(f) / statistics.median(b)})
    load = Path("/proc/loadavg").read_text().split()[:3]
    shares = {}
    for name, cmd, kind in (("axi4 (bench_fe axi4)", [str(now / "bench_fe"), "axi4"], "fe"),
                            ("hex8 (bench_fe hex8)", [str(now / "bench_fe"), "hex8"], "fe"),
                            ("tlm host (bench_tlm)", [str(now / "bench_tlm"), "2.0"], "tlm")):
        got = attribution(cmd, GUARD_FUNCTIONS[kind])
        if got is not None:
            shares[name] = got
    result = {"before": a.before, "pairs": a.pairs, "loadavg": load, "rows": rows, "attribution": shares}
    (ROOT / "bench/results").mkdir(exist_ok=True)
    (ROOT / "bench/results/guard_cost.json").write_text(json.dumps(result, indent=1))
    for r in rows:
        print(f"{r['case']:12s} min {r['before_min']:8.2f} -> {r['after_min']:8.2f} ({100 * (r['ratio_min'] - 1):+.1f} %), "
              f"median {100 * (r['ratio_median'] - 1):+.1f} %")
    for name, got in shares.items():
        print(f"{name}: guards {sum(got.values()):.2f} % of the samples (" +
              ", ".join(f"{f.split('::')[-1]} {v:.2f} %" for f, v in got.items()) + ")")


if __name__ == "__main__":
    main()
