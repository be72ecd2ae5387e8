// Imported first by the node-opcua peers: node-opcua prints its warnings with console.log, and
// the peers keep stdout for what the test reads (a READY line, one JSON document).
console.log = (...args) => console.error(...args);
console.info = (...args) => console.error(...args);
console.warn = (...args) => console.error(...args);
