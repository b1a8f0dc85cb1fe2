// forwarding: a PLC's write of AppliedSequence and its call of Acknowledge,
// passed to thermocomp under the caller's own token; thermocomp decides,
// stores and audits, and its answer becomes the OPC UA status
// (docs/opcua.md, "Forwarded writes and calls").
"use strict";
const { StatusCodes } = require("node-opcua");

// The OPC UA status of thermocomp's answer to a forwarded write or call:
// refusals a PLC should not retry apart from those that pass (busy, shed).
function statusOf(httpStatus, invalid) {
  if (httpStatus === 200 || httpStatus === 201) return StatusCodes.Good;
  if (httpStatus === 401 || httpStatus === 403) return StatusCodes.BadUserAccessDenied;
  if (httpStatus === 429) return StatusCodes.BadTooManyOperations;
  if (httpStatus === 503) return StatusCodes.BadResourceUnavailable;
  if (httpStatus === 404) return StatusCodes.BadNotFound;
  if (httpStatus === 409) return StatusCodes.BadInvalidState;
  if (httpStatus >= 400 && httpStatus < 500) return invalid;
  return StatusCodes.BadInternalError;
}

// A PLC's AppliedSequence, forwarded with its own token.
// `to`: { http, identities, log }.
async function forwardApplied(to, user, machine, axis, sequence, values) {
  const { http, identities, log } = to;
  const token = user ? await identities.tokenFor(user) : null;
  if (!token) return StatusCodes.BadUserAccessDenied;
  const answer = await http.request("POST", `/machines/${encodeURIComponent(machine)}/compensation/applied`, {
    token,
    body: { axis, sequence, ...(values || {}), via: "opcua" },
  });
  const status = statusOf(answer.status, StatusCodes.BadOutOfRange);
  log(`${machine}/${axis}: applied sequence ${sequence} from ${user}: thermocomp answered ${answer.status}`);
  return status;
}

// A column-check request acknowledged by a caller of the Acknowledge method,
// forwarded with the caller's own token.
async function forwardAcknowledge(to, user, machine, requestId) {
  const { http, identities, log } = to;
  const token = user ? await identities.tokenFor(user) : null;
  if (!token) return StatusCodes.BadUserAccessDenied;
  const answer = await http.request(
    "POST",
    `/machines/${encodeURIComponent(machine)}/column-checks/requests/${requestId}/acknowledge`,
    { token, body: {} },
  );
  log(`${machine}: acknowledgement of column-check request ${requestId} from ${user}: thermocomp answered ${answer.status}`);
  return statusOf(answer.status, StatusCodes.BadInvalidArgument);
}

module.exports = { statusOf, forwardApplied, forwardAcknowledge };
