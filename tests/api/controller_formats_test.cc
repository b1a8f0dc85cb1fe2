// The numbers each control receives, against values worked out by hand from
// the units in the controls' manuals (docs/api.md, "Compensation out").
#include "api/controller_formats.h"

#include <gtest/gtest.h>

namespace thermocomp::api {
namespace {

MachineCompensation Example() {
  MachineCompensation c;
  c.machine = "m1";
  c.control_axes = {"X", "Y", "Z", "B"};
  AxisCompensation y;
  y.axis = "Y";
  y.valid = true;
  y.offset_mm = 0.013456;     // at the reference position
  y.slope_um_per_m = -6.164;  // a thermal slope: -6.164 um per metre
  y.reference_position_mm = 120.0;
  y.offset_at_probe_mm = 0.0127164;  // where the datum was probed
  AxisCompensation b;
  b.axis = "B";
  b.valid = true;
  b.offset_mm = b.offset_at_probe_mm = -0.0021;
  AxisCompensation x;
  x.axis = "X";
  x.valid = false;
  x.reason = "no active model";
  c.axes = {x, y, b};
  return c;
}

TEST(ControllerFormatsTest, SinumerikSlopeIsTanBetaNotMicronsPerMetre) {
  // SD43910 $SA_TEMP_COMP_SLOPE: tan(beta), mm per mm. -6.164 um/m is
  // -6.164e-6; written in fixed point (NC syntax), 12 decimals.
  EXPECT_DOUBLE_EQ(SinumerikSlope(-6.164), -6.164e-6);
  const std::string out = RenderForController(Example(), "sinumerik");
  EXPECT_NE(out.find("$SA_TEMP_COMP_ABS_VALUE[Y]=0.013456\n"), std::string::npos) << out;
  EXPECT_NE(out.find("$SA_TEMP_COMP_SLOPE[Y]=-0.000006164000\n"), std::string::npos) << out;
  EXPECT_NE(out.find("$SA_TEMP_COMP_REF_POSITION[Y]=120.000\n"), std::string::npos) << out;
  // An invalid axis with nothing to hold: a comment with its state and
  // reason, then zeros.
  EXPECT_NE(out.find("; X not valid, off: no active model\n$SA_TEMP_COMP_ABS_VALUE[X]=0.000000\n"),
            std::string::npos)
      << out;
}

TEST(ControllerFormatsTest, BeckhoffInTenthsOfMicronsAndMicronsPerMetre) {
  const std::string out = RenderForController(Example(), "beckhoff");
  EXPECT_NE(out.find("Y.temp_comp_offset_0=135\n"), std::string::npos) << out;  // 13.456 um
  EXPECT_NE(out.find("Y.temp_comp_position_0=1200000\n"), std::string::npos) << out;
  EXPECT_NE(out.find("Y.temp_comp_coefficient=-6.164\n"), std::string::npos) << out;
}

TEST(ControllerFormatsTest, OffsetOnlyControlsGetTheOffsetAtTheProbe) {
  EXPECT_NE(RenderForController(Example(), "heidenhain").find("Y=127\n"), std::string::npos);
  EXPECT_NE(RenderForController(Example(), "linuxcnc").find("setp axis.y.eoffset-counts 127\n"),
            std::string::npos);
  MachineCompensation far = Example();
  far.axes[1].offset_at_probe_mm = 3.5;  // Heidenhain takes at most +-3 mm
  EXPECT_NE(RenderForController(far, "heidenhain").find("Y=30000\n"), std::string::npos);
}

TEST(ControllerFormatsTest, FanucVariablesFollowTheControlsAxisOrder) {
  // X Y Z B: B is the control's fourth axis, #5204 (not #5205 by letter).
  const std::string out = RenderForController(Example(), "fanuc");
  EXPECT_NE(out.find("#5202=0.0127\n"), std::string::npos) << out;
  EXPECT_NE(out.find("#5204=-0.0021\n"), std::string::npos) << out;
  EXPECT_EQ(out.find("#5205"), std::string::npos) << out;
  // A lathe configured X Z C: its C is #5203.
  MachineCompensation lathe = Example();
  lathe.control_axes = {"X", "Z", "C"};
  lathe.axes[2].axis = "C";
  EXPECT_NE(RenderForController(lathe, "fanuc").find("#5203=-0.0021\n"), std::string::npos);
}

}  // namespace
}  // namespace thermocomp::api
