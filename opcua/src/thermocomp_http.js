// thermocomp_http: the sidecar's only way to thermocomp, its HTTP API on
// loopback. Every answer is bounded (size and time): a server that hangs or
// floods cannot take the OPC UA face down with it.
"use strict";
const http = require("node:http");

const kMaxBodyBytes = 8 * 1024 * 1024;

class ThermocompHttp {
  // baseUrl: "http://127.0.0.1:8080"; token: a bearer token or "" (a server
  // without tokens serves loopback clients without one).
  constructor({ baseUrl, token = "", timeoutMs = 5000 }) {
    const url = new URL(baseUrl);
    if (url.protocol !== "http:") throw new Error(`--thermocomp must be http:// on loopback, got ${baseUrl}`);
    this.host = url.hostname;
    this.port = Number(url.port || 80);
    this.token = token;
    this.timeoutMs = timeoutMs;
    // Keep-alive: the face polls every machine each half second.
    this.agent = new http.Agent({ keepAlive: true, maxSockets: 4 });
  }

  // Resolves {status, body} (body parsed as JSON when it is JSON); rejects on
  // a transport error, a timeout or an oversized answer.
  request(method, path, { body = undefined, token = this.token } = {}) {
    return new Promise((resolve, reject) => {
      const headers = { Accept: "application/json" };
      if (token) headers.Authorization = `Bearer ${token}`;
      let payload;
      if (body !== undefined) {
        payload = Buffer.from(JSON.stringify(body));
        headers["Content-Type"] = "application/json";
        headers["Content-Length"] = payload.length;
      }
      const req = http.request(
        { host: this.host, port: this.port, method, path: `/api/v1${path}`, headers, agent: this.agent },
        (res) => {
          const chunks = [];
          let size = 0;
          res.on("data", (c) => {
            size += c.length;
            if (size > kMaxBodyBytes) {
              req.destroy(new Error(`answer to ${path} over ${kMaxBodyBytes} bytes`));
              return;
            }
            chunks.push(c);
          });
          res.on("end", () => {
            const text = Buffer.concat(chunks).toString("utf8");
            let parsed = text;
            if ((res.headers["content-type"] || "").includes("json") && text.length > 0) {
              try {
                parsed = JSON.parse(text);
              } catch (e) {
                reject(new Error(`${path}: malformed JSON: ${e.message}`));
                return;
              }
            }
            resolve({ status: res.statusCode, body: parsed });
          });
          res.on("error", reject);
        },
      );
      req.setTimeout(this.timeoutMs, () => req.destroy(new Error(`${path}: no answer in ${this.timeoutMs} ms`)));
      req.on("error", reject);
      if (payload) req.write(payload);
      req.end();
    });
  }

  close() {
    this.agent.destroy();
  }
}

module.exports = { ThermocompHttp };
