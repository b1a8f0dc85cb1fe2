// What thermocomp reads of an MTConnect agent's documents (MTConnect 1.x
// and 2.x XML): the header's instanceId and sequence numbers, the
// Temperature data items a device declares (/probe), the Temperature
// observations it streams (/current, /sample) and the error codes of an
// MTConnectError (OUT_OF_RANGE when the buffer has wrapped past `from`).
// Everything else is ignored. The agent is a remote party: a document that
// is not well-formed XML, has no header, or whose header lacks its
// numbers is InvalidArgument, never a crash; a malformed observation is
// skipped and counted.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"

namespace thermocomp {

struct MtconnectHeader {
  uint64_t instance_id = 0;
  int64_t creation_ms = 0;  // the agent's clock when it wrote the document
  // Streams (and errors, where the agent says): the buffer holds
  // [first_sequence, last_sequence]; next_sequence is where a reader goes on.
  uint64_t first_sequence = 0;
  uint64_t last_sequence = 0;
  uint64_t next_sequence = 0;
};

// One Temperature observation; no value for UNAVAILABLE.
struct TemperatureObservation {
  std::string data_item_id;
  uint64_t sequence = 0;
  int64_t ts_ms = 0;
  std::optional<double> value;
};

// A Temperature data item a device declares (/probe).
struct TemperatureItem {
  std::string id;
  std::string name;
  std::string units;  // CELSIUS in a conforming agent
};

struct MtconnectDocument {
  enum class Kind { kDevices, kStreams, kError };
  Kind kind = Kind::kStreams;
  MtconnectHeader header;
  std::vector<TemperatureItem> items;                // kDevices
  std::vector<TemperatureObservation> temperatures;  // kStreams, in sequence order
  std::vector<std::string> error_codes;              // kError
  int skipped = 0;  // observations with a bad sequence, time or value
  bool HasError(std::string_view code) const;
};

// Parses one document. `device` (a name or uuid; empty: every device)
// keeps only that device's items and observations.
StatusOr<MtconnectDocument> ParseMtconnectDocument(std::string_view xml,
                                                   const std::string& device = "");

}  // namespace thermocomp
