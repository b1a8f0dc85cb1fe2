// The part-error model types on a simulated lathe: fitted, guarded (a
// prediction outside the trained ranges never comes back with a value),
// stored as JSON and rebuilt to the same predictions, and a registry that
// finds them by name.
#include <cmath>

#include <gtest/gtest.h>

#include "service/parts/process/part_model.h"
#include "sim/parts/process_lathe.h"

namespace thermocomp {
namespace {

PartTrainingSet Set(int records, uint64_t seed) {
  const auto sim = SimulateLathe({.seed = seed, .records = records});
  PartTrainingSet set;
  set.target = "size_error_um";
  set.inputs = {"ap_mm", "f_mm_rev", "vc_m_min", "temperature_c"};
  set.x.resize(records, 4);
  set.y.resize(records);
  for (int i = 0; i < records; ++i) {
    for (int k = 0; k < 4; ++k) {
      set.x(i, k) = sim[static_cast<size_t>(i)].values.at(set.inputs[static_cast<size_t>(k)]);
    }
    set.y(i) = sim[static_cast<size_t>(i)].values.at("size_error_um");
  }
  return set;
}

PartInputs Middle() {
  return {{"ap_mm", 1.5}, {"f_mm_rev", 0.2}, {"vc_m_min", 200}, {"temperature_c", 25}};
}

class PartTypes : public ::testing::TestWithParam<const char*> {};

TEST_P(PartTypes, FitsGuardsAndRoundTrips) {
  const PartTrainingSet set = Set(120, 4);
  const PartModelType* type = FindPartModelType(GetParam());
  ASSERT_NE(type, nullptr);
  PartFitOptions options;
  options.neural_hidden = 3;
  options.neural_restarts = 2;
  auto model = type->Fit(set, options);
  ASSERT_TRUE(model.ok()) << model.status().ToString();
  EXPECT_EQ((*model)->type(), GetParam());

  // Inside: a value near the truth (the noise is 1 µm).
  const PartPrediction in = (*model)->Predict(Middle());
  ASSERT_TRUE(in.valid) << in.reason;
  EXPECT_TRUE(in.in_range);
  ASSERT_TRUE(in.value.has_value());
  EXPECT_NEAR(*in.value, LatheTruthSizeErrorUm(1.5, 0.2, 200, 25), 1.5);

  // Outside, by a little and by a lot, one input or two: never a value.
  for (const auto& [name, value] :
       std::vector<std::pair<std::string, double>>{{"ap_mm", kLatheApMm[1] + 0.01},
                                                   {"ap_mm", 10.0},
                                                   {"f_mm_rev", kLatheFeedMmRev[0] - 0.001},
                                                   {"temperature_c", 40}}) {
    PartInputs inputs = Middle();
    inputs[name] = value;
    const PartPrediction out = (*model)->Predict(inputs);
    EXPECT_FALSE(out.valid) << name;
    EXPECT_FALSE(out.in_range) << name;
    EXPECT_FALSE(out.value.has_value()) << name;
    ASSERT_EQ(out.outside.size(), 1u);
    EXPECT_EQ(out.outside[0].name, name);
    EXPECT_DOUBLE_EQ(out.outside[0].value, value);
    EXPECT_LE(out.outside[0].low, out.outside[0].high);
    EXPECT_NE(out.reason.find("outside the trained range"), std::string::npos) << out.reason;
  }
  PartInputs two = Middle();
  two["ap_mm"] = 0.1;
  two["vc_m_min"] = 500;
  EXPECT_EQ((*model)->Predict(two).outside.size(), 2u);
  PartInputs missing = Middle();
  missing.erase("vc_m_min");
  const PartPrediction m = (*model)->Predict(missing);
  EXPECT_FALSE(m.valid);
  EXPECT_FALSE(m.value.has_value());
  EXPECT_EQ(m.missing, std::vector<std::string>{"vc_m_min"});
  PartInputs nan = Middle();
  nan["ap_mm"] = NAN;
  EXPECT_FALSE((*model)->Predict(nan).value.has_value());

  // The trained ranges are the training records' extremes.
  for (size_t k = 0; k < set.inputs.size(); ++k) {
    EXPECT_EQ((*model)->ranges()[k].low, set.x.col(static_cast<Eigen::Index>(k)).minCoeff());
    EXPECT_EQ((*model)->ranges()[k].high, set.x.col(static_cast<Eigen::Index>(k)).maxCoeff());
  }

  // Stored and rebuilt: the same predictions and the same guard.
  const nlohmann::json j = nlohmann::json::parse((*model)->ToJson().dump());
  auto back = PartModelFromJson(j);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ((*back)->target(), "size_error_um");
  // JSON keeps every weight to 17 digits; the network's tanh sums agree to 1e-6.
  EXPECT_NEAR(*(*back)->Predict(Middle()).value, *in.value, 1e-6);
  PartInputs far = Middle();
  far["ap_mm"] = 10;
  EXPECT_FALSE((*back)->Predict(far).valid);

  // A stored model without its ranges is not rebuilt (it could not guard).
  nlohmann::json no_ranges = j;
  no_ranges.erase("ranges");
  EXPECT_FALSE(PartModelFromJson(no_ranges).ok());
}

INSTANTIATE_TEST_SUITE_P(Registered, PartTypes, ::testing::Values("quadratic", "neural"));

TEST(PartTypeRegistry, NamesAndRefusals) {
  ASSERT_GE(PartModelTypes().size(), 2u);
  EXPECT_EQ(PartModelTypes().front()->name(), "quadratic");
  EXPECT_EQ(FindPartModelType("spline"), nullptr);
  EXPECT_FALSE(PartModelFromJson(nlohmann::json{{"type", "spline"}}).ok());
  EXPECT_FALSE(PartModelFromJson(nlohmann::json::array()).ok());

  // Too few records for a network of this size: refused with the reason.
  PartTrainingSet set = Set(12, 2);
  PartFitOptions options;
  options.neural_hidden = 3;
  auto net = FindPartModelType("neural")->Fit(set, options);
  ASSERT_FALSE(net.ok());
  EXPECT_EQ(net.status().code(), Status::Code::kUnprocessable);

  // A constant input is named.
  set = Set(40, 2);
  set.x.col(2).setConstant(200);
  auto q = FindPartModelType("quadratic")->Fit(set, options);
  ASSERT_FALSE(q.ok());
  EXPECT_NE(q.status().message().find("vc_m_min"), std::string::npos) << q.status().message();
}

}  // namespace
}  // namespace thermocomp
