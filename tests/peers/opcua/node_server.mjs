// A node-opcua server with the smartfactory demo model, for interop tests of our OPC UA client
// (libs/opcua/test/client). node-opcua is pinned in /package.json.
//
//   node tests/peers/opcua/node_server.mjs <port> [--variables N] [--max-sessions N]
//       <port>            0 = pick a free port
//       --variables N     for benchmarks (bench/bench_opcua_server): N more Double variables
//                         ns=<i>;s=Demo.Bench.0 .. Demo.Bench.<N-1> in the folder Demo/Bench,
//                         read-only, all with a new value every 100 ms (variable i at step s:
//                         s + i/1000), as `smartfactory opcua server --bench-variables N`
//       --max-sessions N  sessions and connections the server accepts (node-opcua's default: 10)
//       --secure DIR      for the security interop tests: endpoints Basic256Sha256,
//                         Aes128_Sha256_RsaOaep and Aes256_Sha256_RsaPss in Sign and SignAndEncrypt
//                         (and None, for discovery) with the PKI folder DIR (node-opcua's layout:
//                         own/, trusted/certs, rejected/; unknown client certificates are refused)
//       --user NAME:PASSWORD  a user for UserName logins (repeatable)
//
// Listens on 127.0.0.1 with SecurityPolicy None and anonymous access, prints one line
// "READY <port>" on stdout once it accepts connections, and exits when stdin closes (so a test
// that dies takes its server with it). Everything else goes to stderr.
//
// Demo model (as `smartfactory opcua server --demo-model`): namespace "urn:smartfactory:demo",
// object Demo under Objects with
//   Temperature  Double, read-only, changes every 100 ms       ns=<i>;s=Demo.Temperature
//   Counter      Int32, read-write                             ns=<i>;s=Demo.Counter
//   Multiply(a: Double, b: Double) -> Double                   ns=<i>;s=Demo.Multiply
//   RaiseEvent(message: String)  raises a BaseEventType event   ns=<i>;s=Demo.RaiseEvent
// and a BaseEventType event on the Server object every 500 ms ("tick <n>", severity 100).
import "./quiet_console.mjs";
import os from "node:os";
import path from "node:path";
import process from "node:process";

import {
  DataType,
  LocalizedText,
  MessageSecurityMode,
  OPCUACertificateManager,
  OPCUAServer,
  SecurityPolicy,
  StatusCodes,
  Variant,
} from "node-opcua";

import { free_port } from "./loopback_server.mjs";

const log = (...args) => process.stderr.write(`[node_server] ${args.join(" ")}\n`);

function build_demo_model(addressSpace) {
  const ns = addressSpace.registerNamespace("urn:smartfactory:demo");
  const demo = ns.addObject({
    organizedBy: addressSpace.rootFolder.objects,
    browseName: "Demo",
    nodeId: "s=Demo",
  });

  let temperature = 20.0;
  let ticks = 0;
  const temperature_var = ns.addVariable({
    componentOf: demo,
    browseName: "Temperature",
    nodeId: "s=Demo.Temperature",
    dataType: "Double",
    accessLevel: "CurrentRead",
    userAccessLevel: "CurrentRead",
    minimumSamplingInterval: 100,
    value: { dataType: DataType.Double, value: temperature },
  });
  const temperature_timer = setInterval(() => {
    ticks += 1;
    temperature = 20.0 + 5.0 * Math.sin(ticks / 10.0) + ticks * 1e-6;
    temperature_var.setValueFromSource(new Variant({ dataType: DataType.Double, value: temperature }));
  }, 100);

  ns.addVariable({
    componentOf: demo,
    browseName: "Counter",
    nodeId: "s=Demo.Counter",
    dataType: "Int32",
    accessLevel: "CurrentRead | CurrentWrite",
    userAccessLevel: "CurrentRead | CurrentWrite",
    value: { dataType: DataType.Int32, value: 0 },
  });

  const multiply = ns.addMethod(demo, {
    browseName: "Multiply",
    nodeId: "s=Demo.Multiply",
    inputArguments: [
      { name: "a", dataType: DataType.Double, description: "first factor" },
      { name: "b", dataType: DataType.Double, description: "second factor" },
    ],
    outputArguments: [{ name: "product", dataType: DataType.Double, description: "a * b" }],
  });
  multiply.bindMethod(async (inputArguments, _context) => {
    const [a, b] = inputArguments.map((v) => v.value);
    return {
      statusCode: StatusCodes.Good,
      outputArguments: [{ dataType: DataType.Double, value: a * b }],
    };
  });

  const server_object = addressSpace.rootFolder.objects.server;
  const raise = (message, severity) => {
    server_object.raiseEvent("BaseEventType", {
      message: { dataType: DataType.LocalizedText, value: new LocalizedText({ text: message }) },
      severity: { dataType: DataType.UInt16, value: severity },
    });
  };
  const raise_event = ns.addMethod(demo, {
    browseName: "RaiseEvent",
    nodeId: "s=Demo.RaiseEvent",
    inputArguments: [{ name: "message", dataType: DataType.String }],
    outputArguments: [],
  });
  raise_event.bindMethod(async (inputArguments, _context) => {
    raise(inputArguments[0].value ?? "", 500);
    return { statusCode: StatusCodes.Good, outputArguments: [] };
  });

  let events = 0;
  const event_timer = setInterval(() => {
    events += 1;
    raise(`tick ${events}`, 100);
  }, 500);

  return () => {
    clearInterval(temperature_timer);
    clearInterval(event_timer);
  };
}

function build_bench_variables(addressSpace, count) {
  if (count <= 0) {
    return () => {};
  }
  const ns = addressSpace.getNamespace("urn:smartfactory:demo");
  const folder = ns.addObject({
    organizedBy: addressSpace.findNode(`ns=${ns.index};s=Demo`),
    typeDefinition: "FolderType",
    browseName: "Bench",
    nodeId: "s=Demo.Bench",
  });
  const variables = [];
  for (let i = 0; i < count; i += 1) {
    variables.push(
      ns.addVariable({
        organizedBy: folder,
        browseName: `${i}`,
        nodeId: `s=Demo.Bench.${i}`,
        dataType: "Double",
        accessLevel: "CurrentRead",
        userAccessLevel: "CurrentRead",
        minimumSamplingInterval: 100,
        value: { dataType: DataType.Double, value: i / 1000 },
      }),
    );
  }
  let step = 0;
  const timer = setInterval(() => {
    step += 1;
    for (let i = 0; i < variables.length; i += 1) {
      variables[i].setValueFromSource(new Variant({ dataType: DataType.Double, value: step + i / 1000 }));
    }
  }, 100);
  return () => clearInterval(timer);
}

// <port> [--variables N] [--max-sessions N]
function parse_args(args) {
  const options = { port: 0, variables: 0, maxSessions: 0, secure: "", users: {} };
  for (let i = 0; i < args.length; i += 1) {
    if (args[i] === "--secure") {
      options.secure = args[(i += 1)];
    } else if (args[i] === "--user") {
      const [name, ...password] = args[(i += 1)].split(":");
      options.users[name] = password.join(":");
    } else if (args[i] === "--variables") {
      options.variables = Number.parseInt(args[(i += 1)], 10);
    } else if (args[i] === "--max-sessions") {
      options.maxSessions = Number.parseInt(args[(i += 1)], 10);
    } else {
      options.port = Number.parseInt(args[i], 10);
    }
  }
  return options;
}

async function main() {
  const options = parse_args(process.argv.slice(2));
  const port = options.port > 0 ? options.port : await free_port();

  // Keep the PKI (node-opcua creates a self-signed certificate on first start) in one place per
  // user, so later starts are fast and nothing is written into the source tree.
  const pki = path.join(os.tmpdir(), `sf-node-opcua-pki-${process.getuid?.() ?? 0}`);
  const serverCertificateManager = new OPCUACertificateManager({
    rootFolder: options.secure || path.join(pki, "server"),
    automaticallyAcceptUnknownCertificate: !options.secure,
  });
  const secured = options.secure
    ? {
        securityPolicies: [
          SecurityPolicy.None,
          SecurityPolicy.Basic256Sha256,
          SecurityPolicy.Aes128_Sha256_RsaOaep,
          SecurityPolicy.Aes256_Sha256_RsaPss,
        ],
        securityModes: [MessageSecurityMode.None, MessageSecurityMode.Sign, MessageSecurityMode.SignAndEncrypt],
        userManager: { isValidUser: (name, password) => options.users[name] === password },
      }
    : { securityPolicies: [SecurityPolicy.None], securityModes: [MessageSecurityMode.None] };

  const server = new OPCUAServer({
    port,
    host: "127.0.0.1",
    hostname: "127.0.0.1",
    ...secured,
    allowAnonymous: true,
    serverCertificateManager,
    disableDiscovery: true,
    buildInfo: { productName: "smartfactory node-opcua test server" },
    ...(options.maxSessions > 0
      ? {
          maxConnectionsPerEndpoint: options.maxSessions,
          serverCapabilities: { maxSessions: options.maxSessions },
        }
      : {}),
  });
  await server.initialize();
  const stop_demo = build_demo_model(server.engine.addressSpace);
  const stop_bench = build_bench_variables(server.engine.addressSpace, options.variables);
  const stop_model = () => {
    stop_demo();
    stop_bench();
  };
  await server.start();
  process.stdout.write(`READY ${port}\n`);

  let stopping = false;
  const stop = async (why) => {
    if (stopping) {
      return;
    }
    stopping = true;
    log(`stopping (${why})`);
    stop_model();
    try {
      await server.shutdown(0);
    } finally {
      process.exit(0);
    }
  };
  process.stdin.on("end", () => stop("stdin closed"));
  process.stdin.on("close", () => stop("stdin closed"));
  process.stdin.resume();
  process.on("SIGTERM", () => stop("SIGTERM"));
  process.on("SIGINT", () => stop("SIGINT"));
}

main().catch((err) => {
  log(`failed: ${err?.stack ?? err}`);
  process.exit(1);
});
