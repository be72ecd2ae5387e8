// Browsing helpers shared by the node-opcua client peers (history_client.mjs, nodeset_peer.mjs,
// machine_model_client.mjs).
import { BrowseDirection } from "node-opcua";

// Forward hierarchical references of a node, every result field (node class, type definition).
export async function children(session, nodeId) {
  const result = await session.browse({
    nodeId,
    referenceTypeId: "HierarchicalReferences",
    includeSubtypes: true,
    browseDirection: BrowseDirection.Forward,
    resultMask: 63,
  });
  return result.references ?? [];
}

// The NodeId (text) at a "/"-separated path of browse names below nodeId ("i=85" = Objects).
export async function resolve(session, nodeId, path) {
  let at = nodeId;
  for (const name of path.split("/").filter((n) => n.length > 0)) {
    const hit = (await children(session, at)).find((r) => r.browseName.name === name);
    if (!hit) {
      throw new Error(`no '${name}' below ${at}`);
    }
    at = hit.nodeId.toString();
  }
  return at;
}
