// Encodes OPC UA service messages with node-opcua (pinned in /package.json) and prints them as
// C++ string literals for libs/opcua/test/node_opcua_samples_test.cpp, so that our decoder is
// checked against bytes produced by another stack.
//
//   node tests/peers/opcua/encode_samples.js > /tmp/samples.inc
//
// Each message is written as OPC 10000-6 §5.2.9 puts it on the wire: the NodeId of its binary
// DataTypeEncoding followed by the structure. All values are fixed (no clocks, no randomness),
// so running the script again prints the same bytes.
"use strict";

(async () => {
  const { BinaryStream } = await import("node-opcua-binary-stream");
  const { encodeNodeId } = await import("node-opcua-basic-types");
  const { resolveNodeId } = await import("node-opcua-nodeid");
  const t = await import("node-opcua-types");
  const { Variant, DataType, VariantArrayType } = await import("node-opcua-variant");
  const { DataValue, TimestampsToReturn } = await import("node-opcua-data-value");
  const { StatusCodes } = await import("node-opcua-status-code");
  const { DiagnosticInfo, BrowseDirection } = await import("node-opcua-data-model");
  const { DeadbandType } = await import("node-opcua-service-subscription");

  // 2024-05-01T12:00:00.123Z and a second, later instant.
  const t0 = new Date(Date.UTC(2024, 4, 1, 12, 0, 0, 123));
  const t1 = new Date(Date.UTC(2024, 4, 1, 12, 0, 1, 500));

  const requestHeader = (handle) => ({
    authenticationToken: "ns=1;b=AAECAwQFBgcICQoLDA0ODw==",
    timestamp: t0,
    requestHandle: handle,
    returnDiagnostics: 0,
    timeoutHint: 10000,
  });
  const responseHeader = (handle, extra = {}) => ({
    timestamp: t1,
    requestHandle: handle,
    serviceResult: StatusCodes.Good,
    ...extra,
  });

  const samples = {};

  samples.ReadRequest = new t.ReadRequest({
    requestHeader: requestHeader(42),
    maxAge: 500,
    timestampsToReturn: TimestampsToReturn.Both,
    nodesToRead: [
      { nodeId: "ns=2;s=Demo.Static.Scalar.Double", attributeId: 13 },
      { nodeId: "i=2258", attributeId: 13, indexRange: "1:2" },
      {
        nodeId: "ns=3;g=72962B91-FA75-4AE6-8D28-B404DC7DAF63",
        attributeId: 4,
        dataEncoding: { namespaceIndex: 0, name: "Default Binary" },
      },
    ],
  });

  samples.BrowseRequest = new t.BrowseRequest({
    requestHeader: requestHeader(7),
    requestedMaxReferencesPerNode: 100,
    nodesToBrowse: [
      {
        nodeId: "i=85",
        browseDirection: BrowseDirection.Forward,
        referenceTypeId: "i=33",
        includeSubtypes: true,
        nodeClassMask: 0,
        resultMask: 63,
      },
      {
        nodeId: "ns=2;i=70000",
        browseDirection: BrowseDirection.Both,
        referenceTypeId: "i=31",
        includeSubtypes: false,
        nodeClassMask: 3,
        resultMask: 1,
      },
    ],
  });

  samples.CreateSubscriptionRequest = new t.CreateSubscriptionRequest({
    requestHeader: requestHeader(9),
    requestedPublishingInterval: 250,
    requestedLifetimeCount: 1200,
    requestedMaxKeepAliveCount: 10,
    maxNotificationsPerPublish: 0,
    publishingEnabled: true,
    priority: 7,
  });

  samples.CreateMonitoredItemsRequest = new t.CreateMonitoredItemsRequest({
    requestHeader: requestHeader(10),
    subscriptionId: 5,
    timestampsToReturn: TimestampsToReturn.Source,
    itemsToCreate: [
      {
        itemToMonitor: { nodeId: "ns=2;s=Line1.Temperature", attributeId: 13 },
        monitoringMode: t.MonitoringMode.Reporting,
        requestedParameters: {
          clientHandle: 1001,
          samplingInterval: 100,
          filter: new t.DataChangeFilter({
            trigger: t.DataChangeTrigger.StatusValue,
            deadbandType: DeadbandType.Absolute,
            deadbandValue: 0.5,
          }),
          queueSize: 10,
          discardOldest: true,
        },
      },
    ],
  });

  samples.ActivateSessionRequest = new t.ActivateSessionRequest({
    requestHeader: requestHeader(3),
    clientSignature: { algorithm: null, signature: null },
    localeIds: ["en-US", "de-DE"],
    userIdentityToken: new t.UserNameIdentityToken({
      policyId: "username_basic256",
      userName: "operator",
      password: Buffer.from("secret"),
      encryptionAlgorithm: null,
    }),
    userTokenSignature: { algorithm: null, signature: null },
  });

  const dataChange = new t.DataChangeNotification({
    monitoredItems: [
      {
        clientHandle: 1001,
        value: new DataValue({
          value: new Variant({ dataType: DataType.Double, value: 21.5 }),
          sourceTimestamp: t0,
          sourcePicoseconds: 12340,
          serverTimestamp: t1,
        }),
      },
      {
        clientHandle: 1002,
        value: new DataValue({
          value: new Variant({
            dataType: DataType.Int32,
            arrayType: VariantArrayType.Array,
            value: [1, -2, 3],
          }),
          statusCode: StatusCodes.UncertainLastUsableValue,
          serverTimestamp: t1,
        }),
      },
      {
        clientHandle: 1003,
        value: new DataValue({
          value: new Variant({ dataType: DataType.String, value: "candy" }),
        }),
      },
    ],
    diagnosticInfos: [],
  });
  samples.PublishResponse = new t.PublishResponse({
    responseHeader: responseHeader(11),
    subscriptionId: 5,
    availableSequenceNumbers: [1, 2, 3],
    moreNotifications: false,
    notificationMessage: {
      sequenceNumber: 3,
      publishTime: t1,
      notificationData: [
        dataChange,
        new t.StatusChangeNotification({ status: StatusCodes.GoodSubscriptionTransferred }),
      ],
    },
    results: [StatusCodes.Good, StatusCodes.BadSequenceNumberUnknown],
    diagnosticInfos: [],
  });

  samples.ReadResponse = new t.ReadResponse({
    responseHeader: responseHeader(42, { stringTable: ["vendor-code-7", "Sensor offline"] }),
    results: [
      new DataValue({
        value: new Variant({
          dataType: DataType.Double,
          arrayType: VariantArrayType.Matrix,
          dimensions: [2, 3],
          value: [1, 2, 3, 4, 5, 6],
        }),
        sourceTimestamp: t0,
      }),
      new DataValue({
        value: new Variant({
          dataType: DataType.LocalizedText,
          value: { locale: "en", text: "Packing line" },
        }),
      }),
      new DataValue({
        value: new Variant({ dataType: DataType.NodeId, value: resolveNodeId("ns=4;s=Robot/Arm") }),
      }),
      new DataValue({
        value: new Variant({ dataType: DataType.ByteString, value: Buffer.from([0xde, 0xad, 0xbe, 0xef]) }),
      }),
      new DataValue({
        value: new Variant({
          dataType: DataType.Boolean,
          arrayType: VariantArrayType.Array,
          value: [true, false],
        }),
      }),
      new DataValue({ statusCode: StatusCodes.BadNodeIdUnknown }),
    ],
    diagnosticInfos: [
      new DiagnosticInfo({
        symbolicId: 0,
        localizedText: 1,
        additionalInfo: "sensor 3",
        innerStatusCode: StatusCodes.BadCommunicationError,
        innerDiagnosticInfo: new DiagnosticInfo({ additionalInfo: "timeout after 2 s" }),
      }),
    ],
  });

  samples.GetEndpointsResponse = new t.GetEndpointsResponse({
    responseHeader: responseHeader(1),
    endpoints: [
      {
        endpointUrl: "opc.tcp://localhost:4840/candy",
        server: {
          applicationUri: "urn:smartfactory:candy-line",
          productUri: "urn:smartfactory",
          applicationName: { text: "Candy line" },
          applicationType: t.ApplicationType.Server,
          discoveryUrls: ["opc.tcp://localhost:4840/candy"],
        },
        serverCertificate: null,
        securityMode: t.MessageSecurityMode.None,
        securityPolicyUri: "http://opcfoundation.org/UA/SecurityPolicy#None",
        userIdentityTokens: [
          { policyId: "anonymous", tokenType: t.UserTokenType.Anonymous },
          {
            policyId: "username_basic256",
            tokenType: t.UserTokenType.UserName,
            securityPolicyUri: "http://opcfoundation.org/UA/SecurityPolicy#Basic256Sha256",
          },
        ],
        transportProfileUri: "http://opcfoundation.org/UA-Profile/Transport/uatcp-uasc-uabinary",
        securityLevel: 1,
      },
    ],
  });

  samples.WriteRequest = new t.WriteRequest({
    requestHeader: requestHeader(12),
    nodesToWrite: [
      {
        nodeId: "ns=2;s=Line1.Setpoint",
        attributeId: 13,
        value: { value: new Variant({ dataType: DataType.Float, value: 1.5 }) },
      },
      {
        nodeId: "ns=2;s=Line1.Recipe",
        attributeId: 13,
        value: {
          value: new Variant({
            dataType: DataType.UInt16,
            arrayType: VariantArrayType.Array,
            value: [10, 20, 30],
          }),
        },
      },
    ],
  });

  samples.ServiceFault = new t.ServiceFault({
    responseHeader: responseHeader(13, { serviceResult: StatusCodes.BadSessionIdInvalid }),
  });

  const wrap = (hex) => {
    const parts = [];
    for (let i = 0; i < hex.length; i += 96) parts.push(`    "${hex.slice(i, i + 96)}"`);
    return parts.join("\n");
  };
  console.log("// Generated by tests/peers/opcua/encode_samples.js (node-opcua 2.186.4).");
  for (const [name, message] of Object.entries(samples)) {
    const stream = new BinaryStream(64 * 1024);
    encodeNodeId(message.schema.encodingDefaultBinary, stream);
    message.encode(stream);
    const hex = stream.buffer.subarray(0, stream.length).toString("hex");
    console.log(`constexpr std::string_view k${name} =\n${wrap(hex)};`);
  }
})().catch((error) => {
  console.error(error);
  process.exit(1);
});
