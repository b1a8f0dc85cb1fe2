#include "api/body_guard.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>

namespace thermocomp::api {
namespace {

std::string Trimmed(const std::string& s) {
  const size_t first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  const size_t last = s.find_last_not_of(" \t");
  std::string out = s.substr(first, last - first + 1);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// zlib's stream, ended whatever way inflating ends.
class Inflater {
 public:
  Inflater() {
    // 15 + 32: a gzip or a zlib header, told apart by zlib.
    ok_ = inflateInit2(&z_, 15 + 32) == Z_OK;
  }
  ~Inflater() {
    if (ok_) inflateEnd(&z_);
  }
  Inflater(const Inflater&) = delete;
  Inflater& operator=(const Inflater&) = delete;
  bool ok() const { return ok_; }
  z_stream& z() { return z_; }

 private:
  z_stream z_{};
  bool ok_ = false;
};

}  // namespace

BodyEncoding TakeContentEncoding(const httplib::Request& req) {
  auto& headers = const_cast<httplib::Request&>(req).headers;
  const size_t count = headers.count("Content-Encoding");  // names compare case-blind
  if (count == 0) return BodyEncoding::kIdentity;
  const std::string coding = Trimmed(headers.find("Content-Encoding")->second);
  headers.erase("Content-Encoding");
  if (count > 1) return BodyEncoding::kUnsupported;
  if (coding.empty() || coding == "identity") return BodyEncoding::kIdentity;
  if (coding == "gzip" || coding == "x-gzip" || coding == "deflate") {
    return BodyEncoding::kCompressed;
  }
  return BodyEncoding::kUnsupported;
}

InflateResult Inflate(std::string_view in, size_t max_bytes, std::string* out) {
  out->clear();
  if (in.empty()) return InflateResult::kOk;
  Inflater inflater;
  if (!inflater.ok()) return InflateResult::kCorrupt;
  z_stream& z = inflater.z();
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(std::min<size_t>(in.size(), UINT32_MAX));
  std::array<char, 64 * 1024> buffer{};
  while (true) {
    z.next_out = reinterpret_cast<Bytef*>(buffer.data());
    z.avail_out = static_cast<uInt>(buffer.size());
    const int r = inflate(&z, Z_NO_FLUSH);
    if (r != Z_OK && r != Z_STREAM_END) return InflateResult::kCorrupt;
    const size_t produced = buffer.size() - z.avail_out;
    if (out->size() + produced > max_bytes) return InflateResult::kTooLarge;
    out->append(buffer.data(), produced);
    if (r == Z_STREAM_END) {
      if (z.avail_in == 0) return InflateResult::kOk;
      // Another gzip member follows (as `cat a.gz b.gz` makes).
      if (inflateReset(&z) != Z_OK) return InflateResult::kCorrupt;
    } else if (produced == 0 && z.avail_in == 0) {
      return InflateResult::kCorrupt;  // the data ended inside the stream
    }
  }
}

}  // namespace thermocomp::api
