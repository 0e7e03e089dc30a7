#!/usr/bin/env python3
"""Hopsan's own runs of our Hopsan test models against tlm_host's.

Usage: hopsan_cli_compare.py TLM_HOST MODEL.hmf [MODEL.hmf ...]
       hopsan_cli_compare.py --fmu FMU FE_SERVER DECK PORTS TLM_HOST MODEL.hmf

Runs each model in HopsanCLI ($PCS_HOPSAN_CLI: the hopsancli executable of a
Hopsan built outside this repository; skipped, exit 77, when unset) and in
tlm_host, tlm_host logging every step and Hopsan every k-th (at most 10000
samples), and compares every column both write (Hopsan's CSV names,
component#port#variable) at every time Hopsan logs; the two CSV files must
have the same columns in the same order (less Hopsan's Temperature and
HeatFlow, and a subsystem's own port and time columns and a sensor's).

Tolerance: Hopsan's CSV prints 7 significant digits (%e with 6 decimals), so
its value is within half a unit of the 7th digit, 5e-7 of the value; 1e-6
allows for that rounding twice. Added to it, 2e-7 of the column's largest
value, for values near zero where round-off is all that differs: a
turbulent orifice's flow near Δp = 0 is K·√Δp, so a round-off difference of
1e-16 of the pressures (1.5e-9 Pa at 150 bar) makes up to K·√1.5e-9 of flow,
1.8e-7 of the largest flow in the accumulator model (measured: 6e-10 there,
where the runs' linear solves differ, Eigen's LU here and Hopsan's own);
Hopsan's clock, a running sum of the time step, differs from ours (n·dt) by
about n·1e-16·t, far less. A one-step shift in either run (the error this
test is for) differs by 1e-3 to 1 of the value.

With --fmu, the model holds Hopsan's FMIWrapperQ with our FMU (a Hopsan-
convention FMU from fmugen), copied beside the model: fe_server serves two
sessions on an ephemeral loopback port, one for tlm_host (which reads the
wrapper as our FmuQ) and one for Hopsan, each with its own results file.
The same tolerance: both hosts send fe_server the same c and Zc.
"""
import csv
import gzip
import os
import re
import secrets
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from fe_server_process import start_fe_server  # noqa: E402


REFERENCE_SAMPLES = 101


def read_hopsan_csv(path):
    """Columns by name from a CSV in Hopsan's layout (name, alias, unit lines)."""
    with (gzip.open(path, "rt", newline="") if path.endswith(".gz") else open(path, newline="")) as f:
        rows = list(csv.reader(f))
    names = rows[0]
    data = [[float(x) for x in r] for r in rows[3:] if r]
    return {n: [r[i] for r in data] for i, n in enumerate(names)}


def run_ours(tlm_host, model, tmp, env):
    """tlm_host's run of the model, logging every step: (columns, None) or (None, the refusal's first line)."""
    name = os.path.splitext(os.path.basename(model))[0]
    ours = os.path.join(tmp, name + "_ours.csv")
    run = subprocess.run([tlm_host, model, "--set", "simulation.log_every=1", "--out", os.path.join(tmp, name + ".h5"),
                          "--csv", ours, "--quiet"], capture_output=True, text=True, timeout=300, env=env)
    if run.returncode != 0:
        lines = [ln for ln in run.stderr.splitlines() if "note:" not in ln] or [f"exit {run.returncode}"]
        return None, f"exit {run.returncode}: {lines[0]}"
    return read_hopsan_csv(ours), None


def hopsan_samples(ours, at_most):
    """Samples for Hopsan's log: N + 1 with N dividing our steps from t = 0 (every
    second step at least, at most `at_most` samples), so that its samples
    fall exactly on our steps."""
    # Hopsan logs from t = 0 (its log start time) when the run starts before.
    dt = ours["Time"][1] - ours["Time"][0]
    steps = sum(1 for t in ours["Time"] if t > -0.5 * dt) - 1
    stride = next((k for k in range(2, steps + 1) if steps % k == 0 and steps // k + 1 <= at_most), steps)
    return steps // stride + 1


def run_hopsan(hopsan, model, samples, out_csv, tmp, env):
    """HopsanCLI's run of the model into out_csv: None, or why it failed."""
    run = subprocess.run([hopsan, "-m", model, "-s", "hmf", "-l", str(samples), "--resultsFullCSV", out_csv,
                          "--resultsCSVSort", "cols"], capture_output=True, text=True, timeout=300, cwd=tmp, env=env)
    if run.returncode != 0 or not os.path.exists(out_csv):
        tail = (run.stdout + run.stderr).strip().splitlines()[-3:]
        return f"hopsancli exit {run.returncode}: {' / '.join(tail)}"
    return None


def agreement(a, b, model):
    """Hopsan's columns a against ours b: (True or False, what was compared or
    what differs, the largest difference relative to the column's largest value)."""
    # The same columns in the same order, but for Hopsan's Temperature and
    # HeatFlow (the model here is isothermal) and a subsystem's own ports and
    # time (sub#port#…, sub$Time) and a sensor's (the same values are under
    # the names of the components at those nodes) or a scope's.
    subsystems = {n.split("$")[0] for n in a if "$" in n}
    # Sensors, and scopes (SignalSink: Hopsan logs a scope's unconnected input), by their component tags.
    tags = [dict(re.findall(r'(\w+)="([^"]*)"', t)) for t in re.findall(r"<component [^>]*>", open(model).read())]
    sensors = {t.get("name") for t in tags if re.fullmatch(r"(Hydraulic|Mechanic)\w*Sensor|SignalSink", t.get("typename", ""))}
    expected = [n for n in a if not n.endswith("#Temperature") and not n.endswith("#HeatFlow")
                and n.split("#")[0] not in subsystems | sensors and not n.endswith("$Time")]
    if list(b) != expected:
        return False, (f"columns differ from Hopsan's: ours only {[n for n in b if n not in a]}, "
                       f"Hopsan's only {[n for n in expected if n not in b]}, same order: "
                       f"{[n for n in expected if n in b] == [n for n in b if n in a]}"), float("nan")
    common = [n for n in b if n in a and n != "Time"]
    if len(common) < 4:
        return False, f"only {len(common)} columns in common", float("nan")
    dt = b["Time"][1] - b["Time"][0]
    # Hopsan logs from its log start time (0 unless the file says), ours
    # from the run's start (which may be before 0): its times within ours,
    # each matched to our row at the same time.
    if a["Time"][0] < b["Time"][0] - 0.5 * dt or a["Time"][-1] > b["Time"][-1] + 0.5 * dt:
        return False, (f"Hopsan's results span t = {a['Time'][0]:g} to {a['Time'][-1]:g}, "
                       f"ours {b['Time'][0]:g} to {b['Time'][-1]:g}"), float("nan")
    worst, where, largest = 0.0, "", 0.0
    for n in common:
        scale = max(abs(v) for v in b[n])
        for t, va in zip(a["Time"], a[n]):
            vb = b[n][round((t - b["Time"][0]) / dt)]
            if scale > 0:
                largest = max(largest, abs(va - vb) / scale)
            excess = abs(va - vb) - (1e-6 * max(abs(va), abs(vb)) + 2e-7 * scale)
            if excess > worst:
                worst, where = excess, f"{n} at t = {t:g}: Hopsan {va:.7e}, ours {vb:.12e}"
    what = f"{len(common)} columns x {len(a['Time'])} times compared"
    return not where, what + (f"; beyond the tolerance: {where}" if where else ", all within the tolerance"), largest


def compare(hopsan, tlm_host, model, tmp, env):
    """Runs the model in both; prints the comparison; True if within the tolerance."""
    name = os.path.splitext(os.path.basename(model))[0]
    b, refused = run_ours(tlm_host, model, tmp, env)
    if refused:
        print(f"{name}: tlm_host refused it: {refused}")
        return False
    theirs = os.path.join(tmp, name + "_hopsan.csv")
    failed = run_hopsan(hopsan, model, hopsan_samples(b, 10000), theirs, tmp, env)
    if failed:
        print(f"{name}: {failed}")
        return False
    ok, what, _ = agreement(read_hopsan_csv(theirs), b, model)
    print(f"{name}: {what}")
    return ok


def against_references(tlm_host, models, refs, tmp, env):
    """Each model against Hopsan's committed CSV (refs/NAME.csv.gz); the number that failed."""
    failures = 0
    for model in models:
        name = os.path.splitext(os.path.basename(model))[0]
        ref = os.path.join(refs, name + ".csv.gz")
        b, refused = run_ours(tlm_host, model, tmp, env)
        if refused or not os.path.exists(ref):
            print(f"{name}: " + (f"tlm_host refused it: {refused}" if refused else f"no reference {ref}"))
            failures += 1
            continue
        ok, what, _ = agreement(read_hopsan_csv(ref), b, model)
        print(f"{name} (Hopsan's committed results): {what}")
        failures += not ok
    return failures


def write_references(hopsan, tlm_host, models, refs, tmp, env):
    """Hopsan's results of each model into refs/NAME.csv.gz, REFERENCE_SAMPLES samples."""
    os.makedirs(refs, exist_ok=True)
    for model in models:
        name = os.path.splitext(os.path.basename(model))[0]
        b, refused = run_ours(tlm_host, model, tmp, env)
        if refused:
            print(f"{name}: tlm_host refused it: {refused}")
            return 1
        out = os.path.join(tmp, name + "_hopsan.csv")
        failed = run_hopsan(hopsan, model, hopsan_samples(b, REFERENCE_SAMPLES), out, tmp, env)
        if failed:
            print(f"{name}: {failed}")
            return 1
        with open(out, "rb") as f, gzip.GzipFile(os.path.join(refs, name + ".csv.gz"), "wb", mtime=0) as g:
            g.write(f.read())
        print(f"{name}: written ({len(read_hopsan_csv(out)['Time'])} samples)")
    return 0


def corpus(hopsan, tlm_host, folder, agreed_file, tmp, env):
    """Every model of a folder of Hopsan's own (.hmf) in both programs: a
    table (model, Hopsan ran, loaded, agrees, largest difference, why not),
    the counts; 1 when a model agreed_file lists does not agree."""
    agreed = [ln.split("#")[0].strip() for ln in open(agreed_file)] if agreed_file else []
    agreed = [a for a in agreed if a]
    models = sorted(f for f in os.listdir(folder) if f.endswith(".hmf"))
    rows, counts = [], {"models": len(models), "Hopsan runs": 0, "loaded": 0, "agree": 0}
    for f in models:
        name, model = f[:-4], os.path.join(folder, f)
        work = os.path.join(tmp, re.sub(r"\W", "_", name))
        os.makedirs(work, exist_ok=True)
        shutil.copy(model, work)
        model = os.path.join(work, f)
        probe = os.path.join(work, "probe.csv")
        hopsan_failed = run_hopsan(hopsan, model, 2, probe, work, env)
        counts["Hopsan runs"] += not hopsan_failed
        b, refused = run_ours(tlm_host, model, work, env)
        refused = refused and refused.replace(model, f)
        if refused:
            rows.append((name, not hopsan_failed, False, False, float("nan"), refused))
            continue
        counts["loaded"] += 1
        if hopsan_failed:
            rows.append((name, False, True, False, float("nan"), hopsan_failed))
            continue
        theirs = os.path.join(work, "hopsan.csv")
        failed = run_hopsan(hopsan, model, hopsan_samples(b, 10000), theirs, work, env)
        ok, what, largest = (False, failed, float("nan")) if failed else agreement(read_hopsan_csv(theirs), b, model)
        counts["agree"] += ok
        rows.append((name, True, True, ok, largest, "" if ok else what))
    print("| model | Hopsan runs | loaded | agrees | largest difference | why not |")
    print("|---|---|---|---|---|---|")
    yes = {True: "yes", False: "no"}
    for name, h, loaded, ok, largest, why in rows:
        print(f"| {name} | {yes[h]} | {yes[loaded]} | {yes[ok]} | {largest:.1e} | {why.replace('|', '/')} |")
    print(", ".join(f"{k}: {v}" for k, v in counts.items()))
    lost = [name for name, _, _, ok, _, _ in rows if name in agreed and not ok]
    missing = [a for a in agreed if a not in [r[0] for r in rows]]
    for name in lost:
        print(f"FAIL {name} agreed with HopsanCLI ({agreed_file}) and does not now")
    for name in missing:
        print(f"FAIL {name} ({agreed_file}) is not in {folder}")
    return 1 if lost or missing else 0


def main():
    args = sys.argv[1:]
    hopsan = os.environ.get("PCS_HOPSAN_CLI")
    env = dict(os.environ)
    with tempfile.TemporaryDirectory() as tmp:
        if args and args[0] == "--reference":
            refs, tlm_host, models = args[1], args[2], [os.path.abspath(m) for m in args[3:]]
            return 1 if against_references(tlm_host, models, refs, tmp, env) else 0
        if not hopsan:
            print("skipped: set PCS_HOPSAN_CLI to HopsanCLI's hopsancli (Hopsan built outside the repository)")
            return 77
        if args[0] == "--write-reference":
            refs, tlm_host, models = args[1], args[2], [os.path.abspath(m) for m in args[3:]]
            return write_references(hopsan, tlm_host, models, refs, tmp, env)
        if args[0] == "--corpus":
            folder = os.environ.get("PCS_HOPSAN_MODELS")
            if not folder:
                print("skipped: set PCS_HOPSAN_MODELS to Hopsan's 'Models' folder (its source tree)")
                return 77
            tlm_host, sub, agreed_file = args[1], args[2], args[3]
            return corpus(hopsan, tlm_host, os.path.join(folder, sub), agreed_file, tmp, env)
        if args[0] == "--fmu":
            fmu, fe_server, deck, ports, tlm_host, model = args[1:7]
            shutil.copy(fmu, tmp)
            shutil.copy(model, tmp)
            # Two sessions: one for tlm_host, one for Hopsan.
            server, env = start_fe_server(fe_server, deck, ports, os.path.join(tmp, "port"),
                                          ["--sessions", "2", "--out", os.path.join(tmp, "fe_{session}.h5")],
                                          {**os.environ, "PCS_TOKEN": secrets.token_hex(16)}, accept_timeout=60)
            try:
                ok = compare(hopsan, tlm_host, os.path.join(tmp, os.path.basename(model)), tmp, env)
                code = server.wait(timeout=60)
                if code != 0:
                    print(f"fe_server exit {code}:\n{server.stdout.read()[-3000:]}")
                    ok = False
            finally:
                if server.poll() is None:
                    server.kill()
            return 0 if ok else 1
        tlm_host, models = args[0], [os.path.abspath(m) for m in args[1:]]
        failures = sum(not compare(hopsan, tlm_host, m, tmp, env) for m in models)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
