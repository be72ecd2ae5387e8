// node-opcua as the other side of NodeSet2 interop tests (OPC 10000-6 Annex F).
//
//   node tests/peers/opcua/nodeset_peer.mjs load FILE...
//       Starts a node-opcua server with the standard namespace 0 and FILE... (in order), browses
//       it with a node-opcua client and prints, as one JSON document on stdout, every node of the
//       files' namespaces reachable from Objects and from the type hierarchies:
//       {"namespaces": [...], "nodes": [{"nodeId", "browseName", "nodeClass", "path",
//        "typeDefinition", "dataType", "value", "isAbstract"}]}
//       A file node-opcua cannot load makes it exit with status 1 and the reason on stderr.
//
//   node tests/peers/opcua/nodeset_peer.mjs export OUT
//       Builds a small model with node-opcua's address-space API in namespace urn:node-opcua:peer
//       and writes it as NodeSet2 XML to OUT (namespace.toNodeset2XML()); prints on stdout a JSON
//       document of what it built, for the test to compare with what our server serves.
import "./quiet_console.mjs";
import fs from "node:fs";
import process from "node:process";

import {
  AttributeIds,
  DataType,
  NodeClass,
  OPCUAClient,
  VariantArrayType,
  nodesets,
} from "node-opcua";
import { AddressSpace } from "node-opcua-address-space";
import { generateAddressSpace } from "node-opcua-address-space/nodeJS.js";

import { children } from "./browse_util.mjs";
import { start_nodeset_server } from "./loopback_server.mjs";

const log = (...args) => process.stderr.write(`[nodeset_peer] ${args.join(" ")}\n`);

function plain(value) {
  if (value === null || value === undefined) {
    return null;
  }
  if (typeof value === "bigint") {
    return value.toString();
  }
  if (Array.isArray(value) || ArrayBuffer.isView(value)) {
    return Array.from(value, plain);
  }
  if (typeof value === "object") {
    if (typeof value.toString === "function" && value.constructor?.name === "NodeId") {
      return value.toString();
    }
    if ("text" in value && "locale" in value) {
      return value.text;
    }
    const out = {};
    for (const key of Object.keys(value)) {
      if (!key.startsWith("_") && typeof value[key] !== "function") {
        out[key] = plain(value[key]);
      }
    }
    return out;
  }
  return value;
}

async function describe(session, ref, trail, namespaces) {
  const node = {
    nodeId: ref.nodeId.toString(),
    namespace: namespaces[ref.nodeId.namespace],
    browseName: ref.browseName.name,
    nodeClass: NodeClass[ref.nodeClass],
    path: trail,
    typeDefinition: ref.typeDefinition?.toString() ?? null,
  };
  if (ref.nodeClass === NodeClass.Variable) {
    const [value, dataType] = await session.read([
      { nodeId: ref.nodeId, attributeId: AttributeIds.Value },
      { nodeId: ref.nodeId, attributeId: AttributeIds.DataType },
    ]);
    node.value = plain(value.value?.value);
    node.dataType = dataType.value?.value?.toString() ?? null;
  }
  if ([NodeClass.ObjectType, NodeClass.VariableType, NodeClass.ReferenceType].includes(ref.nodeClass)) {
    const [isAbstract] = await session.read([{ nodeId: ref.nodeId, attributeId: AttributeIds.IsAbstract }]);
    node.isAbstract = isAbstract.value?.value ?? null;
  }
  return node;
}

// Depth-first from each root; only nodes outside namespace 0 are reported (and descended into,
// besides the roots' standard children).
async function walk(session, roots, namespaces) {
  const nodes = [];
  const seen = new Set();
  const visit = async (nodeId, trail, depth) => {
    if (depth > 8) {
      return;
    }
    for (const ref of await children(session, nodeId)) {
      const key = ref.nodeId.toString();
      const own = ref.nodeId.namespace !== 0;
      const next = `${trail}/${ref.browseName.name}`;
      if (own && !seen.has(key)) {
        seen.add(key);
        nodes.push(await describe(session, ref, next, namespaces));
      }
      if (own || depth < 1) {
        await visit(ref.nodeId, next, depth + 1);
      }
    }
  };
  for (const [root, name] of roots) {
    await visit(root, name, 0);
  }
  return nodes;
}

async function load(files) {
  const { server, url } = await start_nodeset_server(files);
  const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 1 } });
  await client.connect(url);
  const session = await client.createSession();
  const [ns] = await session.read([{ nodeId: "i=2255", attributeId: AttributeIds.Value }]);
  const namespaces = ns.value.value;
  const roots = [
    ["i=85", "Objects"],
    ["i=58", "Types/BaseObjectType"],
    ["i=62", "Types/BaseVariableType"],
    ["i=31", "Types/References"],
    ["i=24", "Types/BaseDataType"],
  ];
  const nodes = await walk(session, roots, namespaces);
  process.stdout.write(`${JSON.stringify({ namespaces, nodes })}\n`);
  await session.close();
  await client.disconnect();
  await server.shutdown(0);
}

// The model node-opcua writes: a type with a mandatory variable, an instance, variables of
// several built-in types and a method with arguments.
function build_model(addressSpace) {
  const ns = addressSpace.registerNamespace("urn:node-opcua:peer");
  const conveyorType = ns.addObjectType({ browseName: "ConveyorType", nodeId: "i=1000" });
  ns.addVariable({
    componentOf: conveyorType,
    browseName: "Speed",
    nodeId: "i=1001",
    dataType: "Double",
    modellingRule: "Mandatory",
    value: { dataType: DataType.Double, value: 0.5 },
  });
  const conveyor = conveyorType.instantiate({
    browseName: "Conveyor1",
    nodeId: "s=Conveyor1",
    organizedBy: addressSpace.rootFolder.objects,
  });
  conveyor.getComponentByName("Speed").setValueFromSource({ dataType: DataType.Double, value: 1.25 });
  ns.addVariable({
    componentOf: conveyor,
    browseName: "Label",
    nodeId: "s=Conveyor1.Label",
    dataType: "String",
    value: { dataType: DataType.String, value: "belt <A> & B" },
  });
  ns.addVariable({
    componentOf: conveyor,
    browseName: "Slots",
    nodeId: "s=Conveyor1.Slots",
    dataType: "Int32",
    valueRank: 1,
    arrayDimensions: [3],
    value: { dataType: DataType.Int32, arrayType: VariantArrayType.Array, value: new Int32Array([4, 5, 6]) },
  });
  ns.addVariable({
    componentOf: conveyor,
    browseName: "Running",
    nodeId: "s=Conveyor1.Running",
    dataType: "Boolean",
    value: { dataType: DataType.Boolean, value: true },
  });
  ns.addMethod(conveyor, {
    browseName: "Start",
    nodeId: "s=Conveyor1.Start",
    inputArguments: [{ name: "speed", dataType: DataType.Double, description: "m/s" }],
    outputArguments: [{ name: "ok", dataType: DataType.Boolean }],
  });
  return {
    namespace: "urn:node-opcua:peer",
    objectType: { nodeId: "i=1000", browseName: "ConveyorType" },
    object: { nodeId: "s=Conveyor1", browseName: "Conveyor1", typeDefinition: "i=1000" },
    values: { Speed: 1.25, Label: "belt <A> & B", Slots: [4, 5, 6], Running: true },
    method: { browseName: "Start", inputArguments: ["speed"], outputArguments: ["ok"] },
  };
}

async function export_model(out) {
  const addressSpace = AddressSpace.create();
  await generateAddressSpace(addressSpace, [nodesets.standard]);
  const summary = build_model(addressSpace);
  fs.writeFileSync(out, addressSpace.getNamespace(summary.namespace).toNodeset2XML());
  process.stdout.write(`${JSON.stringify(summary)}\n`);
  addressSpace.dispose();
}

async function main() {
  const [command, ...args] = process.argv.slice(2);
  if (command === "load" && args.length > 0) {
    await load(args);
  } else if (command === "export" && args.length === 1) {
    await export_model(args[0]);
  } else {
    log("usage: nodeset_peer.mjs load FILE... | export OUT");
    process.exit(2);
  }
  process.exit(0);
}

main().catch((err) => {
  log(`failed: ${err?.stack ?? err}`);
  process.exit(1);
});
