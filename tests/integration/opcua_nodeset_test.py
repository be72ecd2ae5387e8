"""NodeSet2 interop with node-opcua (OPC 10000-6 Annex F), both directions:

1. Our export (`smartfactory opcua nodeset --demo-model -o demo.xml`) loads in a node-opcua
   server; node-opcua's client browses the demo model with its types, values and the Multiply
   method's arguments.
2. A model node-opcua builds and writes (namespace.toNodeset2XML) loads into our server
   (`opcua server --nodeset`); our client browses it and reads the values node-opcua reported.
3. A broken file is refused with file:line:column and a non-zero exit.
"""
import json
import os
import tempfile

from sftest import Background, binary, check, fail, node_peer, node_peer_result, run, wait_for_line


def cli(*args, check_rc=True):
    return run([binary(), "opcua", *args], timeout=60, check_rc=check_rc)


def cli_json(*args):
    proc = cli(*args, "--json")
    try:
        return json.loads(proc.stdout.strip().splitlines()[-1])
    except (json.JSONDecodeError, IndexError) as e:
        fail(f"opcua {' '.join(args)} printed no JSON ({e}):\n{proc.stdout}\n{proc.stderr}")


def node_json(*args):
    return node_peer_result("opcua/nodeset_peer.mjs", args)


def our_export_in_node_opcua(tmp):
    demo_xml = os.path.join(tmp, "demo.xml")
    cli("nodeset", "--demo-model", "-o", demo_xml)
    seen = node_json("load", demo_xml)
    check("urn:smartfactory:demo" in seen["namespaces"], f"node-opcua registered our namespace: {seen['namespaces']}")
    by_path = {n["path"]: n for n in seen["nodes"]}
    check({"Objects/Demo", "Objects/Demo/Temperature", "Objects/Demo/Counter", "Objects/Demo/Multiply"}
          <= set(by_path), f"node-opcua browses the demo model: {sorted(by_path)}")
    check(by_path["Objects/Demo"]["typeDefinition"].endswith("i=58"), "Demo is a BaseObjectType")
    counter = by_path["Objects/Demo/Counter"]
    check(counter["value"] == 0 and counter["dataType"].endswith("i=6"), f"Counter is an Int32 0: {counter}")
    temperature = by_path["Objects/Demo/Temperature"]
    check(temperature["value"] == 20.0 and temperature["dataType"].endswith("i=11"),
          f"Temperature is the Double 20.0 of the exported model: {temperature}")
    arguments = by_path.get("Objects/Demo/Multiply/InputArguments", {}).get("value") or []
    check([a["name"] for a in arguments] == ["a", "b"] and all(a["dataType"].endswith("i=11") for a in arguments),
          f"Multiply's InputArguments arrive as Argument structures: {arguments}")


def node_export_in_our_server(tmp):
    peer_xml = os.path.join(tmp, "peer.xml")
    built = node_json("export", peer_xml)
    server = Background([binary(), "opcua", "server", "--host", "127.0.0.1", "--advertised-host", "127.0.0.1",
                         "--port", "0", "--nodeset", peer_xml, "--status-interval", "0", "--security", "none"],
                        log=os.path.join(tmp, "server.log"))
    try:
        url = wait_for_line(server, "listening on ", 20).split()[-1]
        ns = f"nsu={built['namespace']};"
        obj = built["object"]
        top = cli_json("browse", url, "--security", "none")
        found = [c for c in top if c["browseName"].endswith(":" + obj["browseName"])]
        check(len(found) == 1, f"Objects organizes {obj['browseName']}: {[c['browseName'] for c in top]}")
        check(found[0]["typeDefinition"].endswith(obj["typeDefinition"].split(";")[-1]),
              f"{obj['browseName']} has the type node-opcua instantiated: {found[0]}")
        children = cli_json("browse", url, "--security", "none", "--node", ns + obj["nodeId"])
        names = {c["browseName"].split(":")[-1]: c for c in children}
        check(set(built["values"]) | {built["method"]["browseName"]} <= set(names),
              f"{obj['browseName']}'s children: {sorted(names)}")
        values = cli_json("read", url, "--security", "none", *[names[name]["nodeId"] for name in built["values"]])
        got = {name: v["value"] for name, v in zip(built["values"], values)}
        check(got == built["values"], f"values read back equal node-opcua's: {got}")
        method = names[built["method"]["browseName"]]["nodeId"]
        arguments = cli_json("browse", url, "--security", "none", "--node", method)
        check({"InputArguments", "OutputArguments"} <= {a["browseName"].split(":")[-1] for a in arguments},
              "the method keeps its argument properties")
    finally:
        rc = server.stop()
    check(rc == 0, "our server with the imported model stops cleanly")


def broken_file_is_refused(tmp):
    bad = os.path.join(tmp, "bad.xml")
    with open(bad, "w") as f:
        f.write('<?xml version="1.0"?>\n<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd">\n'
                '  <UAObject NodeId="ns=1;i=1" BrowseName="1:X"/>\n</UANodeSet>\n')
    proc = cli("nodeset", bad, check_rc=False)
    check(proc.returncode != 0 and f"{bad}:3:3:" in proc.stderr and "NamespaceUris" in proc.stderr,
          f"a NodeId outside the file's namespaces is refused at its line: {proc.stderr.strip()}")
    server = run([binary(), "opcua", "server", "--port", "0", "--nodeset", bad, "--duration", "1", "--security", "none"],
                 timeout=30,
                 check_rc=False)
    check(server.returncode != 0 and f"{bad}:3:3:" in server.stderr, "the server refuses to start with it")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        our_export_in_node_opcua(tmp)
        node_export_in_our_server(tmp)
        broken_file_is_refused(tmp)


main()
