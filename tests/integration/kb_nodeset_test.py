"""`smartfactory kb to-nodeset` turns the candy-factory ontology and the prototype line into a
NodeSet2 that node-opcua loads next to the standard nodeset; a node-opcua client then browses
the candy factory's types, reference types and objects. The same NodeSet2 is loaded into our
own OPC UA server (`smartfactory opcua server --nodeset`) and browsed the same way (skipped only
by a build whose server says NodeSet2 import is not available)."""
import json
import os
import subprocess
import tempfile

from sftest import Background, binary, check, run, skip, wait_for

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NAMESPACE = "http://smartfactory.example/ontology/candy"
PEER = os.path.join(ROOT, "tests", "peers", "knowledge", "nodeset_browse.mjs")

work = tempfile.mkdtemp(prefix="kb_nodeset_")
model = os.path.join(work, "candy.xml")
run([binary(), "kb", "to-nodeset", os.path.join(ROOT, "ontology", "candy-factory.ttl"),
     os.path.join(ROOT, "ontology", "prototype-line.ttl"), os.path.join(ROOT, "ontology", "prototype-snapshot.ttl"),
     "-o", model])
check(os.path.getsize(model) > 10000, f"NodeSet2 written ({os.path.getsize(model)} bytes)")


def browse(args):
    proc = subprocess.run(["node", PEER] + args + ["--namespace", NAMESPACE], capture_output=True, text=True,
                          timeout=180, cwd=ROOT)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-3000:])
    return json.loads(proc.stdout)


def check_model(seen, who):
    types = seen["objectTypes"]
    check(seen["namespaceIndex"] > 0, f"{who}: the candy namespace is registered")
    # rdfs:subClassOf → HasSubtype, up to BaseObjectType.
    chain = []
    t = "ScaraRobot"
    while t in types:
        chain.append(t)
        t = types[t]["supertype"]
    check(chain == ["ScaraRobot", "Robot", "Machine", "Equipment", "FactoryEntity"] and t == "BaseObjectType",
          f"{who}: ScaraRobot's supertypes {chain} end at {t}")
    check(types.get("ArticulatedRobot", {}).get("supertype") == "Robot", f"{who}: ArticulatedRobot is a Robot")
    for name in ("BoxUploader", "BoxDownloader", "Conveyor", "SmartController", "EtherCATSlave", "ServoAxis",
                 "DigitalIO", "LegacyPLC", "Gateway", "CandyBox", "Candy", "CandyType", "BoxType", "Order",
                 "OrderLine", "Operation", "Capability"):
        check(name in types, f"{who}: ObjectType {name}")
    # Datatype properties → variables with mapped DataTypes.
    machine = types["Machine"]["variables"]
    check(machine.get("temperature") == "Double" and machine.get("maxTemperature") == "Double",
          f"{who}: Machine declares temperature and maxTemperature as Double: {machine}")
    check(types["ServoAxis"]["variables"].get("axisIndex") == "Int32", f"{who}: axisIndex is an Int32")
    check(types["DigitalIO"]["variables"].get("digitalValue") == "Boolean", f"{who}: digitalValue is a Boolean")
    check(types["Order"]["variables"].get("dueAt") == "DateTime", f"{who}: dueAt is a DateTime")
    # Object properties → ReferenceTypes; hasComponent is OPC UA's HasComponent.
    refs = seen["referenceTypes"]
    check("hasComponent" not in refs and "isComponentOf" not in refs, f"{who}: part-of maps to HasComponent")
    check(refs.get("connectedTo", {}).get("symmetric") is True, f"{who}: connectedTo is symmetric")
    check(refs.get("processes", {}).get("inverseName") == "processedBy",
          f"{who}: processes has the inverse name processedBy: {refs.get('processes')}")
    check(refs.get("canPerform", {}).get("supertype") == "NonHierarchicalReferences",
          f"{who}: canPerform is a NonHierarchicalReference")
    # Individuals → Objects with HasTypeDefinition, components, references and values.
    objs = seen["objects"]
    robot = objs.get("ScaraRobot1", {})
    check(robot.get("type") == "ScaraRobot", f"{who}: ScaraRobot1 is a ScaraRobot")
    check(robot.get("values", {}).get("temperature") == 41.5, f"{who}: ScaraRobot1's temperature reads 41.5")
    check("ScaraRobot1Controller" in robot.get("components", []),
          f"{who}: its smart controller is a component of ScaraRobot1")
    check(set(robot.get("references", {}).get("canPerform", [])) == {"PickAndPlace", "BoxLoading"},
          f"{who}: ScaraRobot1 canPerform references")
    slave = objs.get("ScaraRobot1Slave", {})
    axes = [c for c in slave.get("components", []) if c.startswith("ScaraRobot1Axis")]
    check(slave.get("type") == "EtherCATSlave" and len(axes) == 8, f"{who}: the EtherCAT slave has 8 axes: {axes}")
    check(objs.get("ScaraRobot1Axis3", {}).get("values", {}).get("position") == 90.0, f"{who}: Axis3 position 90.0")
    check(objs.get("Denso", {}).get("type") == "ArticulatedRobot", f"{who}: the DENSO arm is an ArticulatedRobot")
    check("Box1" in objs and objs["Box1"]["type"] == "CandyBox", f"{who}: Box1 is a CandyBox")


if subprocess.run(["node", "--version"], capture_output=True).returncode != 0:
    skip("node is not installed (scripts/setup installs it)")
if not os.path.isdir(os.path.join(ROOT, "node_modules", "node-opcua")):
    skip("node-opcua is not installed (scripts/setup runs npm ci)")
check_model(browse(["--nodeset", model]), "node-opcua")

# Our server, once it imports NodeSet2.
log = os.path.join(work, "server.log")
server = Background([binary(), "opcua", "server", "--port", "0", "--nodeset", model, "--security", "none"], log=log)
try:
    url = []

    def ready():
        out = server.output()
        for line in out.splitlines():
            if line.startswith("listening on "):
                url.append(line.split()[-1])
                return True
        return not server.alive()

    wait_for(ready, 60, "our OPC UA server to start")
    if not url and "not available" in server.output():
        print(f"SKIP (our server): it cannot import NodeSet2 yet:\n{server.output()[-500:]}", flush=True)
    else:
        check(bool(url), f"our server starts with the NodeSet2:\n{server.output()[-2000:]}")
        check_model(browse(["--url", url[0]]), "our server")
finally:
    server.stop()
