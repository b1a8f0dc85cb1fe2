#include "service/mtconnect/mtconnect_document.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <pugixml.hpp>

#include "core/time_format.h"

namespace thermocomp {

namespace mtconnect_document {

// The element's name without a namespace prefix ("m:Header" -> "Header"):
// agents declare the MTConnect namespaces as the default one, but a prefix
// is legal XML.
std::string_view LocalName(const pugi::xml_node& n) {
  std::string_view name = n.name();
  const size_t colon = name.find(':');
  return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

std::optional<uint64_t> ParseUnsigned(std::string_view s) {
  uint64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

std::optional<double> ParseNumber(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\n' || s.front() == '\t')) {
    s.remove_prefix(1);
  }
  while (!s.empty() && (s.back() == ' ' || s.back() == '\n' || s.back() == '\t')) {
    s.remove_suffix(1);
  }
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

pugi::xml_node Child(const pugi::xml_node& parent, std::string_view local) {
  for (pugi::xml_node c : parent.children()) {
    if (c.type() == pugi::node_element && LocalName(c) == local) return c;
  }
  return {};
}

Status ReadHeader(const pugi::xml_node& root, bool streams, MtconnectHeader& h) {
  const pugi::xml_node header = Child(root, "Header");
  if (!header) return Status::InvalidArgument("MTConnect document without a Header");
  const auto instance = ParseUnsigned(header.attribute("instanceId").value());
  if (!instance) return Status::InvalidArgument("MTConnect Header without an instanceId");
  h.instance_id = *instance;
  h.creation_ms = ParseRfc3339(header.attribute("creationTime").value()).value_or(0);
  const auto first = ParseUnsigned(header.attribute("firstSequence").value());
  const auto last = ParseUnsigned(header.attribute("lastSequence").value());
  const auto next = ParseUnsigned(header.attribute("nextSequence").value());
  if (streams && (!first || !last || !next)) {
    return Status::InvalidArgument("MTConnectStreams Header without its sequence numbers");
  }
  h.first_sequence = first.value_or(0);
  h.last_sequence = last.value_or(0);
  h.next_sequence = next.value_or(0);
  return Status::Ok();
}

bool DeviceMatches(const pugi::xml_node& n, const std::string& device) {
  return device.empty() || device == n.attribute("name").value() ||
         device == n.attribute("uuid").value();
}

void ReadStreams(const pugi::xml_node& root, const std::string& device, MtconnectDocument& doc) {
  const pugi::xml_node streams = Child(root, "Streams");
  for (pugi::xml_node ds : streams.children()) {
    if (LocalName(ds) != "DeviceStream" || !DeviceMatches(ds, device)) continue;
    // Observations sit in ComponentStream/{Samples,Events,Condition}; a
    // walk of the subtree finds them at any depth without knowing each
    // version's nesting.
    struct Walker : pugi::xml_tree_walker {
      MtconnectDocument* doc = nullptr;
      bool for_each(pugi::xml_node& n) override {
        if (n.type() != pugi::node_element || LocalName(n) != "Temperature") return true;
        if (LocalName(n.parent()) != "Samples") return true;
        TemperatureObservation o;
        o.data_item_id = n.attribute("dataItemId").value();
        const auto seq = ParseUnsigned(n.attribute("sequence").value());
        const auto ts = ParseRfc3339(n.attribute("timestamp").value());
        const std::string_view text = n.child_value();
        if (o.data_item_id.empty() || !seq || !ts) {
          ++doc->skipped;
          return true;
        }
        o.sequence = *seq;
        o.ts_ms = *ts;
        if (text != "UNAVAILABLE") {
          o.value = ParseNumber(text);
          if (!o.value) {
            ++doc->skipped;
            return true;
          }
        }
        doc->temperatures.push_back(std::move(o));
        return true;
      }
    } walker;
    walker.doc = &doc;
    ds.traverse(walker);
  }
  // A /sample document groups observations by component; the resampler
  // needs them in the order they happened.
  std::stable_sort(doc.temperatures.begin(), doc.temperatures.end(),
                   [](const TemperatureObservation& a, const TemperatureObservation& b) {
                     return a.sequence < b.sequence;
                   });
}

void ReadDevices(const pugi::xml_node& root, const std::string& device, MtconnectDocument& doc) {
  const pugi::xml_node devices = Child(root, "Devices");
  for (pugi::xml_node d : devices.children()) {
    const std::string_view kind = LocalName(d);
    if ((kind != "Device" && kind != "Agent") || !DeviceMatches(d, device)) continue;
    for (pugi::xpath_node x : d.select_nodes(".//*[local-name()='DataItem']")) {
      const pugi::xml_node item = x.node();
      if (std::strcmp(item.attribute("type").value(), "TEMPERATURE") != 0) continue;
      if (std::strcmp(item.attribute("category").value(), "SAMPLE") != 0) continue;
      TemperatureItem t;
      t.id = item.attribute("id").value();
      t.name = item.attribute("name").value();
      t.units = item.attribute("units").value();
      if (!t.id.empty()) doc.items.push_back(std::move(t));
    }
  }
}

}  // namespace mtconnect_document

bool MtconnectDocument::HasError(std::string_view code) const {
  return std::find(error_codes.begin(), error_codes.end(), code) != error_codes.end();
}

StatusOr<MtconnectDocument> ParseMtconnectDocument(std::string_view xml,
                                                   const std::string& device) {
  namespace md = mtconnect_document;
  pugi::xml_document tree;
  // No DOCTYPE or entity expansion beyond XML's five: pugixml never loads
  // external entities, so a hostile document cannot reach the file system.
  const pugi::xml_parse_result parsed =
      tree.load_buffer(xml.data(), xml.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed) {
    return Status::InvalidArgument(std::string("not well-formed XML: ") + parsed.description() +
                                   " at offset " + std::to_string(parsed.offset));
  }
  const pugi::xml_node root = tree.document_element();
  const std::string_view kind = md::LocalName(root);
  MtconnectDocument doc;
  if (kind == "MTConnectStreams") {
    doc.kind = MtconnectDocument::Kind::kStreams;
    if (Status s = md::ReadHeader(root, true, doc.header); !s.ok()) return s;
    md::ReadStreams(root, device, doc);
  } else if (kind == "MTConnectDevices") {
    doc.kind = MtconnectDocument::Kind::kDevices;
    if (Status s = md::ReadHeader(root, false, doc.header); !s.ok()) return s;
    md::ReadDevices(root, device, doc);
  } else if (kind == "MTConnectError") {
    doc.kind = MtconnectDocument::Kind::kError;
    // The header is optional here: some agents answer an error without one.
    (void)md::ReadHeader(root, false, doc.header);
    for (pugi::xpath_node x : root.select_nodes(".//*[local-name()='Error']")) {
      doc.error_codes.emplace_back(x.node().attribute("errorCode").value());
    }
    if (doc.error_codes.empty()) doc.error_codes.emplace_back("UNKNOWN");
  } else {
    return Status::InvalidArgument("not an MTConnect document: <" + std::string(kind) + ">");
  }
  return doc;
}

}  // namespace thermocomp
