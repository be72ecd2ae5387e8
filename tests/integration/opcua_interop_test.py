"""OPC UA interoperability with node-opcua (OPC 10000-4 services, OPC 10000-6 UA TCP), both directions, on loopback:

1. node-opcua's client against `smartfactory opcua server --demo-model`: endpoints, browse,
   read, write (allowed and refused), call, subscribe, and a Bad status for an unknown node.
2. Our command-line client (`smartfactory opcua browse|read|write|call|subscribe`) against our
   own server and against a node-opcua server with the same demo model.
Values are asserted on both sides.
"""
import json
import math
import os
import subprocess
import tempfile

from sftest import Background, binary, check, fail, node_peer, node_peer_result, run, wait_for_line

DEMO = "nsu=urn:smartfactory:demo;s="


def start_our_server(tmp):
    server = Background([binary(), "opcua", "server", "--host", "127.0.0.1", "--advertised-host", "127.0.0.1",
                         "--port", "0", "--demo-model", "--status-interval", "0",
                         # Interop over SecurityPolicy None (opcua_security_test.py has the
                         # secured endpoints); anonymous users may write and call, as node_client.js does.
                         "--security", "none", "--anonymous", "operator"],
                        log=os.path.join(tmp, "server.log"))
    url = wait_for_line(server, "listening on ", 20).split()[-1]
    check(url.startswith("opc.tcp://127.0.0.1:"), f"our server listens on {url}")
    banner = next((line for line in server.output().splitlines() if "security:" in line), "")
    check("None" in banner and "Basic256Sha256" not in banner,
          f"the banner names no policies where no endpoint signs: {banner}")
    return server, url


def node_client_against(url):
    return node_peer_result("opcua/node_client.js", [url, "--samples", "4"])


def check_node_client_results(out):
    check(out["errors"] == [], f"every node-opcua client step succeeded: {out['errors']}")
    check(any(e["policy"].endswith("#None") and e["mode"] == "None" for e in out["endpoints"]),
          "GetEndpoints offers SecurityPolicy None")
    check(out["namespaces"][0] == "http://opcfoundation.org/UA/" and "urn:smartfactory:demo" in out["namespaces"],
          f"NamespaceArray: {out['namespaces']}")
    check("Server" in out["objects"] and "Demo" in out["objects"], f"Objects holds Server and Demo: {out['objects']}")
    check(sorted(out["demo"]) == ["Counter", "Multiply", "Temperature"], f"Demo's children: {out['demo']}")
    check(out["state"] == 0, "ServerStatus.State is Running (0)")
    t = out["temperature"]
    check(t["type"] == "Double" and t["status"] == "Good" and 10 < t["value"] < 30,
          f"Temperature reads as a plausible Double: {t}")
    check(out["write_temperature"] == "BadNotWritable", f"writing read-only Temperature: {out['write_temperature']}")
    check(out["write_counter"] == "Good", "writing Counter is Good")
    check(out["counter"] == 4242, f"Counter reads back the written 4242: {out['counter']}")
    check(out["multiply"] == {"status": "Good", "outputs": [42]}, f"Multiply(6, 7): {out['multiply']}")
    check(out["unknown"] == "BadNodeIdUnknown", f"an unknown node reads as BadNodeIdUnknown: {out['unknown']}")
    values = [s["value"] for s in out["samples"]]
    check(len(values) >= 4 and all(s["status"] == "Good" for s in out["samples"]),
          f"the subscription delivered {len(values)} Good values")
    check(len(set(values)) >= 3, f"subscribed Temperature values change: {values}")


def cli(*args, timeout=60, check_rc=True):
    return run([binary(), "opcua", *args, "--security", "none"], timeout=timeout, check_rc=check_rc)


def cli_json(*args, timeout=60):
    proc = cli(*args, "--json", timeout=timeout)
    try:
        return json.loads(proc.stdout.strip().splitlines()[-1])
    except (json.JSONDecodeError, IndexError) as e:
        fail(f"opcua {' '.join(args)} printed no JSON ({e}):\n{proc.stdout}\n{proc.stderr}")


def check_our_client_against(url, who, demo_ns_prefix):
    obj = demo_ns_prefix + "Demo"
    children = cli_json("browse", url, "--node", obj)
    names = sorted(c["browseName"].split(":")[-1] for c in children)
    check({"Counter", "Multiply", "Temperature"} <= set(names), f"[{who}] browse Demo: {names}")
    top = cli_json("browse", url)
    check(any(c["browseName"].endswith("Server") for c in top), f"[{who}] browse Objects lists Server")
    temperature = cli_json("read", url, demo_ns_prefix + "Demo.Temperature")[0]
    check(temperature["type"] == "Double" and temperature["status"] == "Good" and 10 < temperature["value"] < 30,
          f"[{who}] read Temperature: {temperature}")
    written = cli_json("write", url, demo_ns_prefix + "Demo.Counter", "17")
    check(written["status"] == "Good", f"[{who}] write Counter = 17: {written}")
    counter = cli_json("read", url, demo_ns_prefix + "Demo.Counter")[0]
    check(counter["value"] == 17 and counter["type"] == "Int32", f"[{who}] Counter reads back 17: {counter}")
    refused = cli("write", url, demo_ns_prefix + "Demo.Temperature", "1.5", "--json", check_rc=False)
    check(refused.returncode != 0 and "BadNotWritable" in refused.stdout,
          f"[{who}] writing Temperature is refused: {refused.stdout.strip()}")
    product = cli_json("call", url, obj, demo_ns_prefix + "Demo.Multiply", "6", "7")
    check(product["outputs"] == [42], f"[{who}] call Multiply(6, 7) = {product['outputs']}")
    proc = cli("subscribe", url, demo_ns_prefix + "Demo.Temperature", "--count", "4", "--interval", "100",
               "--duration", "30", "--json", timeout=60)
    samples = [json.loads(line) for line in proc.stdout.splitlines() if line.startswith("{")]
    values = [s["value"] for s in samples]
    check(len(samples) >= 4 and all(isinstance(v, float) and math.isfinite(v) for v in values),
          f"[{who}] subscribe delivered {len(samples)} Double values")
    check(len(set(values)) >= 3, f"[{who}] subscribed values change: {values}")
    unknown = cli("read", url, demo_ns_prefix + "NoSuchNode", "--json", check_rc=False)
    check(unknown.returncode != 0 and "BadNodeIdUnknown" in unknown.stdout,
          f"[{who}] reading an unknown node reports BadNodeIdUnknown")


def start_node_server(tmp):
    log = open(os.path.join(tmp, "node_server.log"), "w")
    # The peer exits when its stdin closes, so it never outlives the test.
    proc = subprocess.Popen(node_peer("opcua/node_server.mjs") + ["0"], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=log, text=True)
    for line in proc.stdout:
        if line.startswith("READY "):
            return proc, f"opc.tcp://127.0.0.1:{int(line.split()[1])}"
    fail("node-opcua server exited before it was ready")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        server, url = start_our_server(tmp)
        try:
            check_node_client_results(node_client_against(url))
            check_our_client_against(url, "our server", DEMO)
        finally:
            rc = server.stop()
        check(rc == 0, "our server stops cleanly on SIGTERM")

        node, node_url = start_node_server(tmp)
        try:
            check_our_client_against(node_url, "node-opcua server", DEMO)
        finally:
            node.stdin.close()
            node.wait(timeout=20)


main()
