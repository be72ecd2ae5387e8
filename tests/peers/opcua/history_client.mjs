// node-opcua's client reading history (HistoryRead, raw) from an OPC UA server, for the cloud
// gateway's aggregating server tests.
//
//   node tests/peers/opcua/history_client.mjs URL PATH [--page N]
//       PATH: browse names from the Objects folder, "/"-separated (e.g. "line-1/Demo/Counter").
//       Reads the whole history of that Variable, N values per request (default 5), following
//       continuation points, and prints one JSON document on stdout:
//       {"nodeId": ..., "requests": n, "values": [{"value", "status", "sourceTimestamp"}]}
import "./quiet_console.mjs";
import process from "node:process";

import {
  AttributeIds,
  DataType,
  HistoryReadRequest,
  OPCUAClient,
  ReadRawModifiedDetails,
  TimestampsToReturn,
} from "node-opcua";

import { resolve } from "./browse_util.mjs";

// node-opcua holds Int64/UInt64 as [high, low] 32-bit halves.
function plain(variant) {
  const v = variant.value;
  if ((variant.dataType === DataType.Int64 || variant.dataType === DataType.UInt64) && Array.isArray(v)) {
    return v[0] * 2 ** 32 + v[1];
  }
  return typeof v === "bigint" ? Number(v) : v;
}

async function main() {
  const [url, path, ...rest] = process.argv.slice(2);
  const page = rest[0] === "--page" ? Number.parseInt(rest[1], 10) : 5;
  const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 2 } });
  await client.connect(url);
  const session = await client.createSession();
  const nodeId = await resolve(session, "i=85", path);
  const [historizing] = await session.read([{ nodeId, attributeId: AttributeIds.Historizing }]);
  const values = [];
  let continuationPoint = null;
  let requests = 0;
  do {
    const response = await session.historyRead(
      new HistoryReadRequest({
        historyReadDetails: new ReadRawModifiedDetails({
          isReadModified: false,
          startTime: new Date(Date.UTC(2000, 0, 1)),
          endTime: new Date(Date.UTC(2100, 0, 1)),
          numValuesPerNode: page,
          returnBounds: false,
        }),
        timestampsToReturn: TimestampsToReturn.Both,
        releaseContinuationPoints: false,
        nodesToRead: [{ nodeId, continuationPoint }],
      }),
    );
    requests += 1;
    const result = response.results[0];
    if (result.statusCode.isNotGood() && result.statusCode.name !== "GoodNoData") {
      throw new Error(`HistoryRead: ${result.statusCode.toString()}`);
    }
    for (const dv of result.historyData?.dataValues ?? []) {
      values.push({
        value: plain(dv.value),
        status: dv.statusCode.name,
        sourceTimestamp: dv.sourceTimestamp?.toISOString() ?? null,
      });
    }
    continuationPoint = result.continuationPoint && result.continuationPoint.length > 0 ? result.continuationPoint : null;
  } while (continuationPoint && requests < 10000);
  process.stdout.write(`${JSON.stringify({ nodeId, historizing: historizing.value.value, requests, values })}\n`);
  await session.close();
  await client.disconnect();
}

main()
  .then(() => process.exit(0))
  .catch((err) => {
    process.stderr.write(`[history_client] failed: ${err?.stack ?? err}\n`);
    process.exit(1);
  });
