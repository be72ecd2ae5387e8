"""Legacy-machine gateways as processes (docs/shop-floor.md): `smartfactory plant` serves the
line's PLCs on Modbus TCP; `smartfactory gateway` processes for the box uploader and conveyor 1
drive them and take part in the Contract Net over DDS on loopback; a product agent
(`smartfactory agent product`) gets a box uploaded and carried by conveyor 1 onto conveyor 3,
the box's id carried from the uploader's INFORM-DONE into the transport. The plant's snapshot
shows the box where the product was told it is. Each gateway serves its machine's model on its
own OPC UA server: conveyor 1's PLC registers are typed Good variables, Bad (BadNoCommunication)
with the reason while the plant makes its PLC unreachable, Good again once it answers. A bad
configuration is refused with file:line:column, a taken OPC UA port with an error; nothing starts.
"""
import json
import os
import tempfile
import time
import uuid

from sftest import Background, binary, check, fail, json_events, run, source_dir, wait_for, wait_for_line

PARTITION = f"gw-it-{uuid.uuid4().hex[:8]}"


events = json_events


def write_config(folder, machine, kind, port, opcua_port=0, name=None):
    path = os.path.join(folder, f"{name or machine}.yaml")
    with open(path, "w") as f:
        f.write(f"""machine: {machine}
kind: {kind}
layout: {os.path.join(source_dir(), "layouts", "prototype-line.yaml")}
start: execute
modbus: {{host: 127.0.0.1, port: {port}, poll_period_ms: 20}}
dds: {{interface: lo, partition: {PARTITION}}}
opcua: {{port: {opcua_port}}}
""")
    return path


def ua_read(endpoint, node, *paths):
    """Values of a machine model's nodes over OPC UA: {path: (status, type, value)}."""
    # `opcua read` exits 1 when a value is not Good; the JSON still has every value.
    prefix = f"nsu=urn:smartfactory:machines;s={node}."
    proc = run([binary(), "opcua", "read", "--json", endpoint, *[prefix + p for p in paths]], check_rc=False)
    try:
        values = json.loads(proc.stdout)
    except json.JSONDecodeError:
        fail(f"opcua read gave no JSON (exit {proc.returncode}): {proc.stdout}\n{proc.stderr}")
    return {p: (v["status"], v.get("type"), v.get("value")) for p, v in zip(paths, values)}


PLC_TAGS = {"Tags.plc.motor_run": "Boolean", "Tags.plc.exit_eye": "Boolean", "Tags.plc.speed": "Int64",
            "Tags.plc.fault_code": "Int64"}


def plc_unreachable_turns_tags_bad(sf, control, endpoint):
    """Conveyor 1's PLC registers over OPC UA: Good and typed, Bad with the reason while its PLC is
    unreachable, Good again after."""
    good = ua_read(endpoint, "Conveyor1", *PLC_TAGS)
    for path, kind in PLC_TAGS.items():
        check(good[path][0] == "Good" and good[path][1] == kind, f"{path} is a Good {kind}: {good[path]}")
    run([sf, "plant", "faults", "--control", control, "inject", "plc-unreachable:conveyor1"])
    paths = (*PLC_TAGS, "Tags.plc.speed.Reason")
    wait_for(lambda: ua_read(endpoint, "Conveyor1", *paths)["Tags.plc.speed"][0] == "BadNoCommunication", 10,
             "conveyor 1's registers turn Bad over OPC UA")
    bad = ua_read(endpoint, "Conveyor1", *paths)
    for path in PLC_TAGS:
        check(bad[path][0] == "BadNoCommunication", f"{path} is BadNoCommunication: {bad[path]}")
    reason = bad["Tags.plc.speed.Reason"]
    check(reason[0] == "Good" and "does not answer" in reason[2], f"the reason is readable: {reason}")
    run([sf, "plant", "faults", "--control", control, "clear", "plc-unreachable:conveyor1"])
    wait_for(lambda: all(v[0] == "Good" for v in ua_read(endpoint, "Conveyor1", *PLC_TAGS).values()), 10,
             "conveyor 1's registers are Good again once its PLC answers")


def taken_opcua_port_is_refused(sf, folder, plc_port, endpoint):
    """A second gateway for conveyor 1 on the first one's OPC UA port: a clear error, nothing runs."""
    taken = int(endpoint.rsplit(":", 1)[1])
    path = write_config(folder, "conveyor1", "conveyor", plc_port, opcua_port=taken, name="conveyor1-again")
    proc = run([sf, "gateway", "--config", path, "--json"], check_rc=False, timeout=30)
    check(proc.returncode == 1 and "OPC UA server" in proc.stderr,
          f"a taken OPC UA port is an error naming the server (exit {proc.returncode}): {proc.stderr[-500:]}")
    check(not events(proc.stdout, "ready"), "nothing started")


def bad_config_is_refused(sf, folder):
    path = os.path.join(folder, "bad.yaml")
    with open(path, "w") as f:
        f.write("machine: conveyor1\nkind: belt\n")
    started = time.monotonic()
    proc = run([sf, "gateway", "--config", path, "--json"], check_rc=False, timeout=30)
    check(proc.returncode == 2, f"a bad configuration exits 2 (got {proc.returncode})")
    check(f"{path}:2:7: kind: unknown kind 'belt'" in proc.stderr, f"the error names file:line:column: {proc.stderr}")
    check(not events(proc.stdout, "ready") and time.monotonic() - started < 10, "nothing started")


def main():
    sf = binary()
    tmp = tempfile.mkdtemp(prefix="gw-it-")
    bad_config_is_refused(sf, tmp)

    plant = Background([sf, "plant", "--json", "--status-interval", "0"], log=os.path.join(tmp, "plant.log"))
    gateways = {}
    try:
        line = wait_for_line(plant, '{"endpoints"', 20)
        endpoints = {e["machine"]: e for e in json.loads(line)["endpoints"]}
        port = {m: int(e["address"].rsplit(":", 1)[1]) for m, e in endpoints.items() if e["protocol"] == "modbus-tcp"}
        control = endpoints["plant"]["address"]
        for machine, kind in (("uploader", "uploader"), ("conveyor1", "conveyor")):
            config = write_config(tmp, machine, kind, port[machine])
            gateways[machine] = Background([sf, "gateway", "--config", config, "--json", "--status-interval", "1"],
                                           log=os.path.join(tmp, f"{machine}.log"))
        for machine, g in gateways.items():
            wait_for(lambda: any(e["state"] == "Execute" and e["link"] == "up" for e in events(g.output(), "status")),
                     20, f"{machine} in Execute with its PLC up")
        ready = events(gateways["conveyor1"].output(), "ready")[0]
        hop = next((s for s in ready["segments"] if s["from"] == "conveyor1/upload" and s["to"] == "conveyor3"), None)
        check(hop is not None, f"conveyor 1 offers its segment onto conveyor 3: {ready['segments']}")

        product = run([sf, "agent", "product", "--name", "box-1", "--ops", "upload,transport", "--no-route",
                       "--param", "upload.box_type=0", "--param", f"transport.from={hop['from_place']}",
                       "--param", f"transport.to={hop['to_place']}", "--partition", PARTITION, "--json",
                       "--timeout", "60"], timeout=90, check_rc=False)
        check(product.returncode == 0, f"the product finished\n{product.stdout}\n{product.stderr}")
        done = {e["operation"]: e for e in events(product.stdout, "done")}
        check(done["upload"]["contractor"] == "uploader", "the uploader did the upload")
        box = int(done["upload"]["results"]["box"])
        check(box >= 1, f"the upload's INFORM-DONE names the new box: {done['upload']}")
        check(done["transport"]["contractor"] == "conveyor1" and done["transport"]["results"]["box"] == box,
              f"conveyor 1 carried that box: {done['transport']}")

        snapshot = json.loads(run([sf, "plant", "snapshot", "--control", control, "--json"]).stdout)["snapshot"]
        where = next((b for b in snapshot["boxes"] if b["id"] == box), None)
        check(where is not None and where["belt"] == "conveyor3", f"the plant has box {box} on conveyor 3: {where}")
        wait_for(lambda: any(e["done"] == 1 for e in events(gateways["uploader"].output(), "status")), 5,
                 "the uploader's status counts the job done")
        check(ready["opcua"].startswith("opc.tcp://"), f"the ready line names the OPC UA endpoint: {ready}")
        plc_unreachable_turns_tags_bad(sf, control, ready["opcua"])
        taken_opcua_port_is_refused(sf, tmp, port["conveyor1"], ready["opcua"])
    finally:
        codes = {m: g.stop() for m, g in gateways.items()}
        plant.stop()
    for machine, code in codes.items():
        check(code == 0, f"gateway {machine} stops cleanly on SIGTERM (exit {code})"
              + ("" if code == 0 else "\n" + gateways[machine].output()[-2000:]))


if __name__ == "__main__":
    main()
