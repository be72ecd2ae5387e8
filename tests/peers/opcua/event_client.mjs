// node-opcua's client subscribed to the events of a server's Server object (OPC 10000-4
// §5.12.1.4), for the cloud's alarm tests: the aggregating server reports the knowledge loop's
// alarms as AlarmConditionType events (OPC 10000-9 §5.8).
//
//   node tests/peers/opcua/event_client.mjs URL
//       Prints "SUBSCRIBED" once its event monitored item exists, then one JSON line per event
//       it receives: {"eventType", "sourceName", "message", "severity", "conditionId",
//       "conditionName", "activeState", "activeStateId", "ackedStateId", "retain"}.
//       A line "REFRESH" on stdin calls ConditionRefresh (OPC 10000-9 §5.5.7) for its
//       subscription and prints {"refresh": <StatusCode name>}. Ends when stdin closes.
import "./quiet_console.mjs";
import process from "node:process";
import readline from "node:readline";

import { AttributeIds, DataType, OPCUAClient, TimestampsToReturn, constructEventFilter } from "node-opcua";

// Select clauses on BaseEventType (node-opcua's default): the server evaluates each browse path
// without considering the type; "ConditionId" is the NodeId attribute of a ConditionType.
const fields = [
  "EventType",
  "SourceName",
  "Message",
  "Severity",
  "ConditionId",
  "ConditionName",
  "ActiveState",
  "ActiveState.Id",
  "AckedState.Id",
  "Retain",
];

function plain(variant) {
  const v = variant?.value;
  if (v === null || v === undefined) {
    return null;
  }
  if (typeof v === "object" && "text" in v) {
    return v.text; // LocalizedText
  }
  if (typeof v === "object" && typeof v.toString === "function" && !Array.isArray(v)) {
    return v.toString(); // NodeId
  }
  return v;
}

async function main() {
  const [url] = process.argv.slice(2);
  const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 2 } });
  await client.connect(url);
  const session = await client.createSession();
  const subscription = await session.createSubscription2({
    requestedPublishingInterval: 50,
    requestedLifetimeCount: 6000,
    requestedMaxKeepAliveCount: 20,
    maxNotificationsPerPublish: 1000,
    publishingEnabled: true,
    priority: 1,
  });
  const item = await subscription.monitor(
    { nodeId: "i=2253", attributeId: AttributeIds.EventNotifier },
    { samplingInterval: 0, queueSize: 1000, discardOldest: false, filter: constructEventFilter(fields) },
    TimestampsToReturn.Neither,
  );
  item.on("changed", (values) => {
    const [eventType, sourceName, message, severity, conditionId, conditionName, active, activeId, ackedId, retain] =
      values.map(plain);
    const event = { eventType, sourceName, message, severity, conditionId, conditionName };
    Object.assign(event, { activeState: active, activeStateId: activeId, ackedStateId: ackedId, retain });
    process.stdout.write(`${JSON.stringify(event)}\n`);
  });
  process.stdout.write("SUBSCRIBED\n");
  const stop = async () => {
    await subscription.terminate().catch(() => {});
    await session.close().catch(() => {});
    await client.disconnect();
    process.exit(0);
  };
  const lines = readline.createInterface({ input: process.stdin });
  lines.on("line", async (line) => {
    if (line.trim() !== "REFRESH") {
      return;
    }
    const result = await session.call({
      objectId: "i=2782", // ConditionType
      methodId: "i=3875", // ConditionRefresh
      inputArguments: [{ dataType: DataType.UInt32, value: subscription.subscriptionId }],
    });
    process.stdout.write(`${JSON.stringify({ refresh: result.statusCode.name })}\n`);
  });
  lines.on("close", stop);
}

main().catch((err) => {
  process.stderr.write(`[event_client] failed: ${err?.stack ?? err}\n`);
  process.exit(1);
});
