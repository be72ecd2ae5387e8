// Helpers shared by the node-opcua client peers (node_client.js, node_secure_client.js).
"use strict";

// `promise`, or a rejection naming `what` after `ms` milliseconds.
function withTimeout(promise, ms, what) {
  let timer;
  const timeout = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new Error(`${what}: no answer within ${ms} ms`)), ms);
  });
  return Promise.race([promise, timeout]).finally(() => clearTimeout(timer));
}

module.exports = { withTimeout };
