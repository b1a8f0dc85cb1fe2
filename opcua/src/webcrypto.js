// node-opcua 2.18x takes its random numbers from globalThis.crypto, which
// Node.js has on the global object from 19 on; Debian 12's Node.js 18 has
// the same Web Crypto object as require("node:crypto").webcrypto only.
// Required before node-opcua by every entry point.
"use strict";
if (!globalThis.crypto) {
  Object.defineProperty(globalThis, "crypto", { value: require("node:crypto").webcrypto, configurable: true });
}
