"""The cloud gateway as processes (paper §VI): two `smartfactory opcua server --demo-model` processes,
`smartfactory cloud` writing to SQLite with its aggregating OPC UA server, and node-opcua's client
reading the history through that server.

1. Every Counter value written on a server reaches the database once, in order (each value is
   written after the previous one is stored, so the test knows exactly what was produced). The
   servers run with their default security (Sign and SignAndEncrypt only) and the gateway picks
   the most secure endpoint; all share one PKI folder, as processes of one installation do.
2. node-opcua reads the same history from the aggregating server, a few values per request,
   following continuation points (over SecurityPolicy None, which the config asks for); our
   client reads the aggregated live value over its most secure endpoint.
3. A bad config is refused with file:line:column; an unreachable server is reported while the
   others work.
"""
import json
import os
import tempfile

from sftest import Background, binary, check, fail, node_peer, run, wait_for, wait_for_line

COUNTER = "nsu=urn:smartfactory:demo;s=Demo.Counter"


def start_server(tmp, name):
    server = Background([binary(), "opcua", "server", "--host", "127.0.0.1", "--advertised-host", "127.0.0.1",
                         "--port", "0", "--demo-model", "--status-interval", "0", "--pki", pki(tmp)],
                        log=os.path.join(tmp, f"{name}.log"))
    return server, wait_for_line(server, "listening on ", 20).split()[-1]


def pki(tmp):
    return os.path.join(tmp, "pki")


def write_config(tmp, servers, extra=""):
    path = os.path.join(tmp, "cloud.yaml")
    with open(path, "w") as f:
        f.write(f"historian:\n  url: sqlite:{tmp}/history.db\n  buffer: {tmp}/buffer\n  flush_ms: 20\n"
                f"pki: {pki(tmp)}\n"
                "aggregating_server:\n  host: 127.0.0.1\n  port: 0\n  security: none,sign,encrypt\nservers:\n")
        for name, url in servers:
            f.write(f"  - name: {name}\n    url: {url}\n    publishing_interval_ms: 50\n"
                    "    sampling_interval_ms: 10\n    subscribe:\n      - browse_path: /Objects/Demo\n"
                    "        depth: 1\n")
        f.write(extra)
    return path


def stored_counter(tmp, server):
    proc = run([binary(), "history", "query", "--db", f"sqlite:{tmp}/history.db", "--series", "/Objects/Demo/Counter",
                "--server", server, "--from", "-1h", "--json"], check_rc=False)
    if proc.returncode != 0:
        return []
    return [s["value"] for s in json.loads(proc.stdout)["samples"]]


def main():
    with tempfile.TemporaryDirectory() as tmp:
        a, url_a = start_server(tmp, "line-a")
        b, url_b = start_server(tmp, "line-b")
        config = write_config(tmp, [("line-a", url_a), ("line-b", url_b), ("line-gone", "opc.tcp://127.0.0.1:1")])
        gateway = Background([binary(), "cloud", "--config", config, "--status-interval", "1"],
                             log=os.path.join(tmp, "cloud.log"))
        try:
            port = int(wait_for_line(gateway, "aggregating server on port ", 30).split()[-1])
            wait_for(lambda: stored_counter(tmp, "line-a") == [0], 30, "line-a's Counter stored with its first value")
            written = [0]
            for value in range(1, 9):
                run([binary(), "opcua", "write", url_a, COUNTER, str(value), "--pki", pki(tmp)])
                written.append(value)
                wait_for(lambda: stored_counter(tmp, "line-a") == written, 30, f"Counter = {value} stored")
            check(stored_counter(tmp, "line-a") == list(range(0, 9)),
                  "the database holds every Counter value of line-a once, in order")
            check(stored_counter(tmp, "line-b") == [0], "line-b's untouched Counter holds its one value")

            peer = run(node_peer("opcua/history_client.mjs") + [f"opc.tcp://127.0.0.1:{port}", "line-a/Demo/Counter",
                                                                 "--page", "3"], timeout=120)
            history = json.loads(peer.stdout.strip().splitlines()[-1])
            check([v["value"] for v in history["values"]] == list(range(0, 9)),
                  f"node-opcua reads the same history through the aggregating server: {history['values']}")
            check(history["requests"] >= 3, f"three values per request: {history['requests']} requests")
            check(history["historizing"] is True, "the aggregated Counter is Historizing")
            live = json.loads(run([binary(), "opcua", "read", f"opc.tcp://127.0.0.1:{port}",
                                   "nsu=urn:smartfactory:cloud;s=line-a/Demo/Counter", "--json",
                                   "--pki", pki(tmp)]).stdout)
            check(live[0]["value"] == 8, f"our client reads the aggregated live Counter over a secured channel: {live}")
            check(f"{url_a}: endpoint Aes256_Sha256_RsaPss SignAndEncrypt" in gateway.output(),
                  "the gateway connects to the servers over their most secure endpoint")

            wait_for(lambda: "line-gone" in gateway.output() and "127.0.0.1:1" in gateway.output(), 30,
                     "the unreachable server is reported")
        finally:
            rc = gateway.stop()
            a.stop()
            b.stop()
        check(rc == 0, "the gateway stops cleanly on SIGTERM")

        bad = os.path.join(tmp, "bad.yaml")
        with open(bad, "w") as f:
            f.write("servers:\n  - name: x\n    url: http://nope\n    subscribe: [{node: i=85}]\n")
        proc = run([binary(), "cloud", "--config", bad], check_rc=False)
        check(proc.returncode == 2 and f"{bad}:3:10" in proc.stderr,
              f"a bad config is refused with its place: {proc.stderr.strip()}")


main()
