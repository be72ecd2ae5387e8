// What the node-opcua peers share: a free loopback port, and a node-opcua server on it that
// offers SecurityPolicy None only and loads NodeSet2 files (nodeset_peer.mjs, knowledge's
// nodeset_browse.mjs).
import net from "node:net";
import os from "node:os";
import path from "node:path";
import process from "node:process";

import { MessageSecurityMode, OPCUACertificateManager, OPCUAServer, SecurityPolicy, nodesets } from "node-opcua";

// Port 0 is asked of the kernel first, because node-opcua builds its endpoint URLs before it
// listens and would advertise port 0.
export async function free_port() {
  return new Promise((resolve, reject) => {
    const s = net.createServer();
    s.once("error", reject);
    s.listen(0, "127.0.0.1", () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

// A started server with namespace 0 and `files` (NodeSet2 paths); {server, url}.
export async function start_nodeset_server(files) {
  const port = await free_port();
  const pki = path.join(os.tmpdir(), `sf-node-opcua-pki-${process.getuid?.() ?? 0}`);
  const server = new OPCUAServer({
    port,
    host: "127.0.0.1",
    hostname: "127.0.0.1",
    securityPolicies: [SecurityPolicy.None],
    securityModes: [MessageSecurityMode.None],
    allowAnonymous: true,
    disableDiscovery: true,
    serverCertificateManager: new OPCUACertificateManager({ rootFolder: path.join(pki, "server") }),
    nodeset_filename: [nodesets.standard, ...files.map((f) => path.resolve(f))],
  });
  await server.initialize();
  await server.start();
  return { server, url: `opc.tcp://127.0.0.1:${port}` };
}
