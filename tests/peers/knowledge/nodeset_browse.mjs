// node-opcua (pinned in /package.json) as the peer of `smartfactory kb to-nodeset`: loads the
// generated NodeSet2 into a node-opcua server next to the standard nodeset, then browses it
// with a node-opcua client and prints what it found as one JSON object on stdout, which
// tests/integration/kb_nodeset_test.py asserts.
//
//   node tests/peers/knowledge/nodeset_browse.mjs --nodeset model.xml --namespace URI
//   node tests/peers/knowledge/nodeset_browse.mjs --url opc.tcp://127.0.0.1:4840 --namespace URI
//
// With --url it only browses a running server (ours). The JSON:
//   { "namespaceIndex": n,
//     "objectTypes": { "<name>": { "supertype": "<name>", "variables": { "<name>": "<DataType>" } } },
//     "referenceTypes": { "<name>": { "supertype": "<name>", "inverseName": "..", "symmetric": bool } },
//     "objects": { "<name>": { "type": "<name>", "parent": "<name>", "components": [...],
//                              "references": { "<reftype>": [...] }, "values": { "<name>": value } } } }
import "../opcua/quiet_console.mjs";
import process from "node:process";

import {
  AttributeIds,
  BrowseDirection,
  MessageSecurityMode,
  NodeClass,
  OPCUAClient,
  SecurityPolicy,
} from "node-opcua";

import { start_nodeset_server } from "../opcua/loopback_server.mjs";

function parse_args(argv) {
  const args = { nodeset: null, url: null, namespace: null };
  for (let i = 0; i < argv.length; i += 2) {
    const key = argv[i].replace(/^--/, "");
    if (!(key in args)) throw new Error(`unknown option ${argv[i]}`);
    args[key] = argv[i + 1];
  }
  if (!args.namespace || (!args.nodeset && !args.url)) {
    throw new Error("usage: nodeset_browse.mjs (--nodeset FILE | --url URL) --namespace URI");
  }
  return args;
}

// All references of one kind from a node (following continuation points).
async function browse(session, nodeId, referenceTypeId, direction = BrowseDirection.Forward, includeSubtypes = true) {
  let result = await session.browse({ nodeId, referenceTypeId, browseDirection: direction, includeSubtypes, resultMask: 63 });
  const refs = [...(result.references ?? [])];
  while (result.continuationPoint && result.continuationPoint.length) {
    result = await session.browseNext(result.continuationPoint, false);
    refs.push(...(result.references ?? []));
  }
  return refs;
}

const name = (ref) => ref.browseName.name;

async function subtypes(session, root, ns, out, visit) {
  for (const ref of await browse(session, root, "HasSubtype", BrowseDirection.Forward, false)) {
    if (ref.nodeId.namespace === ns) {
      out[name(ref)] = await visit(ref);
    }
    await subtypes(session, ref.nodeId, ns, out, visit);
  }
}

async function supertype_name(session, nodeId) {
  const up = await browse(session, nodeId, "HasSubtype", BrowseDirection.Inverse, false);
  return up.length ? name(up[0]) : null;
}

async function data_type_name(session, nodeId) {
  const dv = await session.read({ nodeId, attributeId: AttributeIds.DataType });
  const dt = await session.read({ nodeId: dv.value.value, attributeId: AttributeIds.BrowseName });
  return dt.value.value.name;
}

async function object_types(session, ns) {
  const out = {};
  await subtypes(session, "i=58", ns, out, async (ref) => {
    const variables = {};
    for (const child of await browse(session, ref.nodeId, "HierarchicalReferences")) {
      if (child.nodeClass === NodeClass.Variable) variables[name(child)] = await data_type_name(session, child.nodeId);
    }
    return { supertype: await supertype_name(session, ref.nodeId), variables };
  });
  return out;
}

async function reference_types(session, ns) {
  const out = {};
  for (const root of ["i=32", "i=47"]) {
    await subtypes(session, root, ns, out, async (ref) => {
      const inverse = await session.read({ nodeId: ref.nodeId, attributeId: AttributeIds.InverseName });
      const symmetric = await session.read({ nodeId: ref.nodeId, attributeId: AttributeIds.Symmetric });
      return {
        supertype: await supertype_name(session, ref.nodeId),
        inverseName: inverse.value.value?.text ?? null,
        symmetric: symmetric.value.value === true,
      };
    });
  }
  return out;
}

async function describe_object(session, ref, parent, ns, out) {
  const entry = { type: null, parent, components: [], references: {}, values: {} };
  out[name(ref)] = entry;
  const types = await browse(session, ref.nodeId, "HasTypeDefinition");
  entry.type = types.length ? name(types[0]) : null;
  for (const child of await browse(session, ref.nodeId, "References")) {
    const kind = (await session.read({ nodeId: child.referenceTypeId, attributeId: AttributeIds.BrowseName })).value.value.name;
    if (kind === "HasTypeDefinition") continue;
    if (child.nodeClass === NodeClass.Variable) {
      const dv = await session.read({ nodeId: child.nodeId, attributeId: AttributeIds.Value });
      const v = dv.value.value;
      entry.values[name(child)] = v instanceof Date ? v.toISOString() : (typeof v === "bigint" ? Number(v) : v);
    } else if (kind === "HasComponent" && child.nodeId.namespace === ns) {
      entry.components.push(name(child));
      if (!(name(child) in out)) await describe_object(session, child, name(ref), ns, out);
    } else if (child.nodeId.namespace === ns) {
      (entry.references[kind] ??= []).push(name(child));
    }
  }
}

async function objects(session, ns) {
  const out = {};
  for (const folder of await browse(session, "i=85", "Organizes")) {
    if (folder.nodeId.namespace !== ns) continue;
    for (const ref of await browse(session, folder.nodeId, "Organizes")) {
      if (!(name(ref) in out)) await describe_object(session, ref, null, ns, out);
    }
  }
  return out;
}

async function main() {
  const args = parse_args(process.argv.slice(2));
  const started = args.nodeset ? await start_nodeset_server([args.nodeset]) : null;
  const url = started ? started.url : args.url;
  const client = OPCUAClient.create({
    endpointMustExist: false,
    securityMode: MessageSecurityMode.None,
    securityPolicy: SecurityPolicy.None,
    connectionStrategy: { maxRetry: 2, initialDelay: 200, maxDelay: 500 },
  });
  await client.connect(url);
  const session = await client.createSession();
  const nsArray = (await session.read({ nodeId: "i=2255", attributeId: AttributeIds.Value })).value.value;
  const ns = nsArray.indexOf(args.namespace);
  const result = { namespaceIndex: ns, objectTypes: {}, referenceTypes: {}, objects: {} };
  if (ns > 0) {
    result.objectTypes = await object_types(session, ns);
    result.referenceTypes = await reference_types(session, ns);
    result.objects = await objects(session, ns);
  }
  await session.close();
  await client.disconnect();
  if (started) await started.server.shutdown(0);
  process.stdout.write(JSON.stringify(result) + "\n");
  process.exit(0);
}

main().catch((err) => {
  process.stderr.write(`[nodeset_browse] failed: ${err?.stack ?? err}\n`);
  process.exit(2);
});
