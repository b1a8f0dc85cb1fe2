// The MTConnect documents thermocomp reads, from recorded answers
// (tests/data/mtconnect/, written for these tests): probe, current, sample,
// OUT_OF_RANGE, and what a hostile agent may send instead.
#include "service/mtconnect/mtconnect_document.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/time_format.h"

namespace thermocomp {
namespace {

std::string Recorded(const std::string& name) {
  std::ifstream in(std::string(THERMOCOMP_SOURCE_DIR) + "/tests/data/mtconnect/" + name);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_FALSE(text.str().empty()) << name;
  return text.str();
}

int64_t At(const char* rfc3339) {
  return ParseRfc3339(rfc3339).value();
}

TEST(MtconnectDocument, ProbeListsTheDevicesTemperatureSamples) {
  auto doc = ParseMtconnectDocument(Recorded("probe.xml"));
  ASSERT_TRUE(doc.ok()) << doc.status().ToString();
  EXPECT_EQ(doc->kind, MtconnectDocument::Kind::kDevices);
  EXPECT_EQ(doc->header.instance_id, 1773560000u);
  ASSERT_EQ(doc->items.size(), 3u);  // the CONDITION and the POSITION are not samples of it
  EXPECT_EQ(doc->items[0].id, "bed_temp");
  EXPECT_EQ(doc->items[0].name, "Tbed");
  EXPECT_EQ(doc->items[0].units, "CELSIUS");
  EXPECT_EQ(doc->items[1].id, "spindle_temp");
  EXPECT_EQ(doc->items[2].id, "motor_temp");
  EXPECT_TRUE(ParseMtconnectDocument(Recorded("probe.xml"), "no-such-device")->items.empty());
}

TEST(MtconnectDocument, CurrentGivesTheHeaderAndTheDevicesTemperatures) {
  auto doc = ParseMtconnectDocument(Recorded("current.xml"), "vmc-1");
  ASSERT_TRUE(doc.ok()) << doc.status().ToString();
  EXPECT_EQ(doc->kind, MtconnectDocument::Kind::kStreams);
  EXPECT_EQ(doc->header.instance_id, 1773560000u);
  EXPECT_EQ(doc->header.first_sequence, 1u);
  EXPECT_EQ(doc->header.last_sequence, 3u);
  EXPECT_EQ(doc->header.next_sequence, 4u);
  EXPECT_EQ(doc->header.creation_ms, At("2026-03-15T10:03:30Z"));
  // In sequence order, the other device's left out; microseconds to ms.
  ASSERT_EQ(doc->temperatures.size(), 2u);
  EXPECT_EQ(doc->temperatures[0].data_item_id, "spindle_temp");
  EXPECT_EQ(doc->temperatures[0].sequence, 2u);
  EXPECT_EQ(doc->temperatures[0].ts_ms, At("2026-03-15T10:00:05.123Z"));
  EXPECT_DOUBLE_EQ(doc->temperatures[0].value.value(), 20.0);
  EXPECT_EQ(doc->temperatures[1].data_item_id, "bed_temp");
  EXPECT_DOUBLE_EQ(doc->temperatures[1].value.value(), 19.0);
  // Without a device, every device's.
  EXPECT_EQ(ParseMtconnectDocument(Recorded("current.xml"))->temperatures.size(), 3u);
}

TEST(MtconnectDocument, SampleIsPutInSequenceOrderWithUnavailableAndBadOnesSkipped) {
  auto doc = ParseMtconnectDocument(Recorded("sample.xml"), "vmc-1-uuid");
  ASSERT_TRUE(doc.ok()) << doc.status().ToString();
  EXPECT_EQ(doc->header.next_sequence, 10u);
  ASSERT_EQ(doc->temperatures.size(), 4u);
  EXPECT_EQ(doc->temperatures[0].sequence, 4u);
  EXPECT_EQ(doc->temperatures[1].sequence, 5u);
  EXPECT_EQ(doc->temperatures[1].data_item_id, "bed_temp");
  EXPECT_FALSE(doc->temperatures[1].value.has_value());  // UNAVAILABLE
  EXPECT_EQ(doc->temperatures[2].data_item_id, "motor_temp");
  EXPECT_EQ(doc->temperatures[3].sequence, 8u);
  EXPECT_DOUBLE_EQ(doc->temperatures[3].value.value(), 19.5);
  EXPECT_EQ(doc->skipped, 2);  // "warm", and a time that is none
}

TEST(MtconnectDocument, OutOfRangeIsAnErrorDocument) {
  auto doc = ParseMtconnectDocument(Recorded("out_of_range.xml"));
  ASSERT_TRUE(doc.ok()) << doc.status().ToString();
  EXPECT_EQ(doc->kind, MtconnectDocument::Kind::kError);
  EXPECT_TRUE(doc->HasError("OUT_OF_RANGE"));
  EXPECT_EQ(doc->header.instance_id, 1773560500u);
}

TEST(MtconnectDocument, HostileDocumentsAreRefusedNotFatal) {
  for (const std::string& xml :
       {Recorded("truncated.xml"), std::string(), std::string("not xml at all"),
        std::string("<html><body>proxy error</body></html>"),
        std::string("<MTConnectStreams><Streams/></MTConnectStreams>"),  // no header
        std::string("<MTConnectStreams><Header instanceId=\"-1\" nextSequence=\"1\" "
                    "firstSequence=\"1\" lastSequence=\"1\"/></MTConnectStreams>"),
        std::string("<MTConnectStreams><Header instanceId=\"1\"/></MTConnectStreams>"),
        std::string("<!DOCTYPE x [<!ENTITY e SYSTEM \"file:///etc/passwd\">]>"
                    "<MTConnectStreams>&e;</MTConnectStreams>")}) {
    auto doc = ParseMtconnectDocument(xml);
    EXPECT_FALSE(doc.ok()) << xml;
    EXPECT_EQ(doc.status().code(), Status::Code::kInvalidArgument) << xml;
  }
  // Deep nesting is walked without recursion on our side and bounded by
  // the document's size: a million levels must neither crash nor hang.
  std::string deep =
      "<MTConnectStreams><Header instanceId=\"1\" nextSequence=\"1\" "
      "firstSequence=\"1\" lastSequence=\"1\"/><Streams><DeviceStream>";
  for (int i = 0; i < 100000; ++i) deep += "<a>";
  for (int i = 0; i < 100000; ++i) deep += "</a>";
  deep += "</DeviceStream></Streams></MTConnectStreams>";
  auto doc = ParseMtconnectDocument(deep);
  ASSERT_TRUE(doc.ok());
  EXPECT_TRUE(doc->temperatures.empty());
}

TEST(MtconnectDocument, NonFiniteValuesAreParsedForIngestToRefuse) {
  const std::string xml =
      "<MTConnectStreams><Header instanceId=\"7\" nextSequence=\"3\" firstSequence=\"1\" "
      "lastSequence=\"2\"/><Streams><DeviceStream name=\"d\"><ComponentStream><Samples>"
      "<Temperature dataItemId=\"t\" sequence=\"1\" timestamp=\"2026-03-15T10:00:00Z\">nan"
      "</Temperature><Temperature dataItemId=\"t\" sequence=\"2\" "
      "timestamp=\"2026-03-15T10:00:01Z\"> 1e308 </Temperature></Samples></ComponentStream>"
      "</DeviceStream></Streams></MTConnectStreams>";
  auto doc = ParseMtconnectDocument(xml);
  ASSERT_TRUE(doc.ok()) << doc.status().ToString();
  ASSERT_EQ(doc->temperatures.size(), 2u);
  EXPECT_TRUE(std::isnan(doc->temperatures[0].value.value()));
  EXPECT_DOUBLE_EQ(doc->temperatures[1].value.value(), 1e308);
}

}  // namespace
}  // namespace thermocomp
