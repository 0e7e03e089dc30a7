#!/usr/bin/python3
"""Calibration with its check: fit named parameters of a hammer scene's
monolithic model to named targets (tlm_fit), then confirm the fit with one
co-simulation per condition (the elastic bodies in fe_server, the same
hydraulics in tlm_host) and report each target's residual in both.

  fit_confirm.py [--scene rig|elastic] [--stop S] [--out DIR] [--jobs N]
                 [--confirm-tolerance R] -- TLM_FIT_ARGUMENTS...

Everything after "--" goes to tlm_fit as it is (its --fit, --condition,
--target, --set, --tolerance; tlm_fit --help). The scene names the model
pair: rig (scenes/hammer_rig: model.tlm fitted, model_elastic.tlm with
deck.k co-simulated, the main job's scene) or elastic (scenes/hammer_monolithic
fitted, scenes/hammer_elastic co-simulated). Each co-simulation gets the
tlm_fit --set values (but simulation.*: the fit's run length and step are
the monolithic model's), its condition's values and the fitted ones, runs S
simulated seconds at the FMU's coupling step (default 1.2: the settle time
of 0.3 s and 15 or more blows), and its percussion report is compared with
the same targets.

The fitted model and the co-simulation differ by what the monolithic model
lumps (the elastic piston's rebound, the moving housing: 0.4-1.9 % in
frequency on the rig scene's main job), so the confirmation's tolerance is
its own: default 0.05, and a residual beyond it is marked.

Output in DIR (default out/fit): fit.txt (tlm_fit's table), one folder per
condition (fe.h5, host.h5, host.json, the logs) and confirm.md (the table).
Exit codes: 0 the fit met its targets and every co-simulated residual is
within the confirmation's tolerance, 2 bad arguments, 3 a parameter to fit
that the co-simulation's model does not have (said before fitting), 4 a co-simulation failed, 5 a
co-simulated residual beyond the tolerance; tlm_fit's own exit code when
the fit itself fails (no co-simulation is run then).
"""
import argparse
import concurrent.futures
import json
import os
import pathlib
import re
import secrets
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
BUILD = pathlib.Path(os.environ.get("PCS_BUILD_DIR", str(ROOT / "build")))

# scene: fitted model, co-simulated host model, built scene folder, port table, FMU
SCENES = {
    "rig": ("scenes/hammer_rig/model.tlm", "scenes/hammer_rig/model_elastic.tlm", "hammer_rig",
            "scenes/hammer_rig/ports.cfg", "hammer_rig.fmu"),
    "elastic": ("scenes/hammer_monolithic/model.tlm", "scenes/hammer_elastic/model.tlm", "hammer_elastic",
                "scenes/hammer_elastic/ports.cfg", "hammer_elastic.fmu"),
}

# tlm_fit's figures and where the percussion report's JSON holds them.
JSON_KEY = {"frequency": "frequency_Hz", "v_impact": "impact_velocity_m_s", "stroke": "stroke_m",
            "p_in": "inlet_pressure_Pa", "q_in": "inlet_flow_m3_s", "P_in": "input_power_W",
            "W": "blow_energy_J", "P_out": "output_power_W", "efficiency": "efficiency"}


class Refused(Exception):
    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


def options(args, name):
    """The values of tlm_fit option NAME among ARGS, as "--name V" or "--name=V"."""
    out = []
    for i, a in enumerate(args):
        if a == name and i + 1 < len(args):
            out.append(args[i + 1])
        elif a.startswith(name + "="):
            out.append(a[len(name) + 1:])
    return out


def parse_fit_table(text):
    """Fitted values ("--set C.P=V" after "to use the fit:") and the targets'
    rows ("COND: FIGURE [unit]  wanted  got  residual %") of tlm_fit's table."""
    fitted = re.findall(r"--set (\S+=\S+)", text.split("to use the fit:")[-1]) if "to use the fit:" in text else []
    targets = []
    for line in text.splitlines():
        m = re.match(r"\s*(\S+): (\S+) \[[^\]]*\]\s+(\S+)\s+(\S+)\s+([-+]?[\d.]+) %", line)
        if m:
            targets.append({"condition": m.group(1), "figure": m.group(2), "wanted": float(m.group(3)),
                            "fitted_model": float(m.group(4))})
    return fitted, targets


def components_of(model_path):
    """The component names of a model file's *COMPONENT block."""
    names, block = set(), None
    for line in pathlib.Path(model_path).read_text().splitlines():
        s = line.strip()
        if not s or s.startswith("$"):
            continue
        if s.startswith("*"):
            block = s.upper()
            continue
        if block == "*COMPONENT":
            names.add(s.split(",")[0].strip())
    return names


def figure_of(report, figure):
    if figure.startswith("peak_"):
        return report["peak_pressure_Pa"][figure[len("peak_"):]]
    return report[JSON_KEY[figure]]


def cosimulate(scene, sets, stop, folder):
    """One co-simulation: fe_server on an ephemeral loopback port with a fresh
    token, tlm_host on the scene's co-simulated model with SETS; returns its
    percussion report."""
    _, host_model, built, ports, fmu = SCENES[scene]
    scene_dir = BUILD / "scenes" / built
    folder.mkdir(parents=True, exist_ok=True)
    port_file = folder / "port"
    port_file.unlink(missing_ok=True)
    env = dict(os.environ, PCS_TOKEN=secrets.token_hex(16))  # never on a command line
    with open(folder / "fe_server.log", "w") as server_log:
        server = subprocess.Popen([str(BUILD / "fe_server/fe_server"), "--model", "deck.k", "--ports", str(ROOT / ports),
                                   "--listen", "127.0.0.1:0", "--port-file", str(port_file), "--out",
                                   str(folder / "fe.h5"), "--accept-timeout", "60"],
                                  cwd=scene_dir, env=env, stdout=server_log, stderr=subprocess.STDOUT)
    try:
        for _ in range(400):
            if port_file.exists() and port_file.read_text().strip():
                break
            if server.poll() is not None:
                break
            time.sleep(0.05)
        else:
            raise Refused(4, f"{folder.name}: fe_server wrote no port in 20 s (see {folder / 'fe_server.log'})")
        if server.poll() is not None:
            raise Refused(4, f"{folder.name}: fe_server stopped before the host came "
                             f"(exit {server.returncode}, see {folder / 'fe_server.log'})")
        cmd = [str(BUILD / "tlm_host/tlm_host"), str(ROOT / host_model), "--fmu", str(scene_dir / fmu), "--server",
               f"127.0.0.1:{port_file.read_text().strip()}", "--quiet", "--out", str(folder / "host.h5"),
               "--report", str(folder / "host.json"), "--set", "simulation.timestep=1e-5",
               "--set", "simulation.log_every=2", "--set", f"simulation.stoptime={stop}"]
        for s in sets:
            cmd += ["--set", s]
        with open(folder / "tlm_host.log", "w") as host_log:
            host = subprocess.run(cmd, env=env, stdout=host_log, stderr=subprocess.STDOUT)
        server_rc = server.wait(timeout=120)
    finally:
        if server.poll() is None:
            server.kill()
            server.wait()
    if host.returncode != 0:
        tail = (folder / "tlm_host.log").read_text().strip().splitlines()[-1:] or ["(no message)"]
        raise Refused(4, f"{folder.name}: tlm_host exit {host.returncode}: {tail[0]}")
    if server_rc != 0:
        raise Refused(4, f"{folder.name}: fe_server exit {server_rc} (see {folder / 'fe_server.log'})")
    return json.loads((folder / "host.json").read_text())


def main():
    argv = sys.argv[1:]
    if "--" not in argv:
        if any(a in ("-h", "--help") for a in argv):
            print(__doc__)
            return 0
        print("fit_confirm.py: give tlm_fit's arguments after '--' (fit_confirm.py --help)", file=sys.stderr)
        return 2
    cut = argv.index("--")
    ap = argparse.ArgumentParser(prog="fit_confirm.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", choices=sorted(SCENES), default="rig")
    ap.add_argument("--stop", type=float, default=1.2)
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "out/fit")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--confirm-tolerance", type=float, default=0.05)
    args = ap.parse_args(argv[:cut])
    fit_args = argv[cut + 1:]
    if not 0.3 < args.stop <= 100:
        print(f"fit_confirm.py: --stop {args.stop}: the report settles for 0.3 s and needs 3 blows after it; "
              "give more than 0.3 (1.2 by default)", file=sys.stderr)
        return 2
    if args.jobs < 1 or not 0 < args.confirm_tolerance < 1:
        print("fit_confirm.py: --jobs at least 1, --confirm-tolerance in (0, 1)", file=sys.stderr)
        return 2
    model, host_model = SCENES[args.scene][:2]
    # Every parameter to fit must be in the co-simulated model too: said
    # before the fit's minutes are spent.
    have = components_of(ROOT / host_model)
    for item in options(fit_args, "--fit"):
        for name in (n for n in item.split(",") if n):
            comp = name.split(".")[0]
            if comp not in have:
                print(f"fit_confirm.py: --fit {name.split('=')[0].split(':')[0]}: component '{comp}' is not in the "
                      f"co-simulation's model {host_model}: fit what both models share (the hydraulics), or fit "
                      "the monolithic model alone with tlm_fit", file=sys.stderr)
                return 3
    args.out.mkdir(parents=True, exist_ok=True)
    fit_file = args.out / "fit.txt"
    fit_file.unlink(missing_ok=True)
    print(f"fit_confirm.py: fitting {model} (tlm_fit), then one co-simulation per condition", flush=True)
    rc = subprocess.run([str(BUILD / "tlm_host/tlm_fit"), str(ROOT / model), *fit_args, "--report",
                         str(fit_file)]).returncode
    if rc != 0:
        print(f"fit_confirm.py: tlm_fit exit {rc}: no co-simulation to confirm", file=sys.stderr)
        return rc
    fitted, targets = parse_fit_table(fit_file.read_text())
    if not fitted or not targets:
        print(f"fit_confirm.py: {fit_file} holds no fitted values or targets", file=sys.stderr)
        return 4
    try:
        # The fit's simulation.* settings (its run length, its step) are the
        # monolithic model's: the co-simulation runs --stop seconds at the
        # FMU's coupling step.
        # A condition's own simulation.* values are the fit's too.
        common = [c for c in options(fit_args, "--set") if not c.startswith("simulation.")]
        conditions = {}
        for c in options(fit_args, "--condition"):
            name, _, sets = c.partition(":")
            conditions[name] = [s for s in sets.split(",") if s and not s.startswith("simulation.")]
        if not conditions:
            conditions = {"model": []}
        wanted = sorted({t["condition"] for t in targets})
        print(f"fit_confirm.py: co-simulating {len(wanted)} condition(s), {args.stop:g} s each, "
              f"{min(args.jobs, len(wanted))} at a time, with " + " ".join(fitted), flush=True)
        t0 = time.monotonic()
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as ex:
            futs = {name: ex.submit(cosimulate, args.scene, common + conditions.get(name, []) + fitted, args.stop,
                                    args.out / name) for name in wanted}
            reports = {name: f.result() for name, f in futs.items()}
    except Refused as e:
        print(f"fit_confirm.py: {e}", file=sys.stderr)
        return e.code
    lines = ["| target | wanted (SI) | fitted model | residual | co-simulation | residual |", "|---|---|---|---|---|---|"]
    beyond = []
    for t in targets:
        co = figure_of(reports[t["condition"]], t["figure"])
        r_fit, r_co = t["fitted_model"] / t["wanted"] - 1, co / t["wanted"] - 1
        mark = "" if abs(r_co) <= args.confirm_tolerance else " (**beyond**)"
        if mark:
            beyond.append(f"{t['condition']}: {t['figure']}: {100 * r_co:+.2f} %")
        lines.append(f"| {t['condition']}: {t['figure']} | {t['wanted']:.6g} | {t['fitted_model']:.6g} | "
                     f"{100 * r_fit:+.3f} % | {co:.6g} | {100 * r_co:+.3f} %{mark} |")
    md = [f"# Fit of {model}, confirmed by co-simulation", "",
          f"Fitted (tlm_fit, {fit_file.name}): " + ", ".join(f"`{f}`" for f in fitted) + ".",
          f"Co-simulated: {host_model} with the scene's deck, {args.stop:g} s per condition "
          f"({time.monotonic() - t0:.0f} s of wall); confirmation tolerance {100 * args.confirm_tolerance:g} %.",
          "", *lines, ""]
    (args.out / "confirm.md").write_text("\n".join(md) + "\n")
    print("\n".join(lines))
    print(f"fit_confirm.py: {args.out / 'confirm.md'}")
    for b in beyond:
        print(f"fit_confirm.py: co-simulated residual beyond {100 * args.confirm_tolerance:g} %: {b}", file=sys.stderr)
    return 5 if beyond else 0


if __name__ == "__main__":
    sys.exit(main())
