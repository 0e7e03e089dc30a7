"""fe_server started by a Python test: on an ephemeral loopback port, its
port read from the port file it writes after binding (every wait bounded)."""
import os
import subprocess
import time


def start_fe_server(fe_server, deck, ports, port_file, extra, env, accept_timeout=30):
    """fe_server for `deck` and `ports` (one port table, or a list of them:
    a session of several FMUs) listening on 127.0.0.1:0; returns the process
    and `env` with the FMU pointed at it ($PCS_SERVER_HOST/PORT)."""
    tables = []
    for table in (ports if isinstance(ports, (list, tuple)) else [ports]):
        tables += ["--ports", str(table)]
    server = subprocess.Popen([str(fe_server), "--model", str(deck)] + tables + ["--listen", "127.0.0.1:0",
                               "--port-file", str(port_file), "--accept-timeout", str(accept_timeout), "--quiet"] +
                              [str(a) for a in extra],
                              env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    port = ""
    for _ in range(500):  # 10 s at most
        if os.path.exists(port_file):
            with open(port_file) as f:
                port = f.read().strip()
            if port:
                break
        time.sleep(0.02)
    return server, {**env, "PCS_SERVER_HOST": "127.0.0.1", "PCS_SERVER_PORT": port or "0"}
