// Compressed request bodies, inflated by this server rather than by
// cpp-httplib, whose request inflation has no bound (a 510 KB gzip body
// inflates to 512 MiB in memory). The request's Content-Encoding is read
// and taken off the request before httplib reads the body, so the body is
// read as sent, within max_body_bytes; the handler's wrapper then
// inflates it, stopping as soon as the output passes the limit.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <httplib.h>

namespace thermocomp::api {

enum class BodyEncoding {
  kIdentity,     // no Content-Encoding, or "identity"
  kCompressed,   // gzip, x-gzip or deflate (zlib or gzip framing)
  kUnsupported,  // anything else, or more than one coding: 415
};

// The request's Content-Encoding; the header is removed from `req` (which
// the hooks are shown as const) so httplib does not inflate the body.
BodyEncoding TakeContentEncoding(const httplib::Request& req);

enum class InflateResult { kOk, kTooLarge, kCorrupt };

// Inflates gzip or zlib data (one or more gzip members) into *out; stops
// with kTooLarge as soon as the output would exceed max_bytes, so memory
// stays within max_bytes plus one buffer.
InflateResult Inflate(std::string_view in, size_t max_bytes, std::string* out);

}  // namespace thermocomp::api
