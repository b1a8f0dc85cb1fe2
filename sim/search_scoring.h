// How an effect search did on a simulated machine whose hidden effects are
// known: which were named as the truth has them (kind, sensor or signal,
// axis, event within a minute, tau within 1.5x; an asymmetric lag with
// both taus within 1.5x; a sensor acting through two lags as two lag terms
// of that sensor; a sensor fault as a reported fault of that sensor with
// its onset within a day), which added effects are false (every added
// effect that matches no truth), which of those are companions (a form of
// a temperature response added next to a named truth, correcting its
// form rather than naming anything), and the held-out error against the
// noise floor (the probe's noise about the true drift plus the declared
// sensors' noise through their coefficients).
//
// TrueEffectGain measures what the truth is worth to the validation the
// search uses (blocked, paired), so a study can tell effects the data can
// show from effects they cannot. Shared by the tests and bench/search_quality.
#pragma once

#include <string>
#include <vector>

#include "model/block_validation.h"
#include "model/effect_search.h"
#include "sim/sim_recording.h"

namespace thermocomp {

struct SearchScore {
  int hidden = 0;
  int named = 0;                        // hidden effects named right
  std::vector<std::string> missed;      // hidden effects not named
  std::vector<std::string> extras;      // added effects and sensor faults that match none
  std::vector<std::string> companions;  // of the extras, forms added next to a named truth
  double holdout_rmse_mm = 0;           // of the extended model
  double noise_floor_mm = 0;
  bool AllNamed() const { return named == hidden; }
  double FloorRatio() const { return holdout_rmse_mm / noise_floor_mm; }
};

// Whether `term` names `truth` (never for a sensor fault).
bool NamesTrueEffect(const EffectTerm& term, const TrueEffect& truth);

// Whether `fault` is the reported form of `truth` (a sensor fault).
bool NamesTrueFault(const SensorFault& fault, const TrueEffect& truth);

// The term a search should add for `truth` (not for a sensor fault).
EffectTerm TrueTerm(const TrueEffect& truth);

// "lag of Tsp tau 4 min", for reports.
std::string DescribeTrueEffect(const TrueEffect& truth);

// `true_drift` is ToSearchInput's per-row noise-free drift.
SearchScore ScoreSearch(const SimRecording& rec, const EffectSearchInput& input,
                        const std::vector<double>& true_drift, const EffectSearchResult& result);

// What adding all hidden terms with their true time constants to the
// declared model gains in blocked cross-validation on the training rows,
// blocked as the search blocks them (days, or runs when fewer than
// options.min_blocks days). Sensor faults are left out. Fails when the
// rows cannot be fitted.
StatusOr<PairedGain> TrueEffectGain(const SimRecording& rec, const EffectSearchInput& input,
                                    const EffectSearchOptions& options);

// The strongest single candidate (GenerateCandidates, on the grid) that
// is not of a true effect's kind and source, validated as TrueEffectGain
// validates the truth, on the rows the true terms are known on: when it
// gains as much as the truth, the data cannot tell the truth from it (a
// proxy sharing its heat source). Fails when nothing is hidden.
struct RivalGain {
  EffectTerm term;
  PairedGain gain;
};
StatusOr<RivalGain> BestRivalGain(const SimRecording& rec, const EffectSearchInput& input,
                                  const EffectSearchOptions& options);

// Whether a gain passes the search's bar: at least min_gain and t >= min_t,
// or the strong rule (>= strong_gain, all blocks but strong_lost_blocks won,
// at least strong_min_blocks blocks).
bool PassesBar(const PairedGain& gain, const EffectSearchOptions& options);
// The strong rule alone.
bool PassesStrongRule(const PairedGain& gain, const EffectSearchOptions& options);

// A machine of a study: family 'A' (VirtualMachine), 'B' (ColumnMachine,
// 60 s), 'C' (B logged every 15 s, probed), 'D' (B logged every 15 s with
// continuous displacement instead of probing), with the hidden effects
// named in `scenario` joined by '+' ("lag+signal", HiddenEffectName or
// ColumnEffectName; "" hides nothing), over `days` (0: the family's
// default, 30 or 24), starting 2026-03-01. "fault_drift", "fault_step" and
// "fault_lost_contact" corrupt the readings of the declared sensor with the
// largest coefficient from 60 % of the recording on (sim/sensor_fault.h),
// the fault a TrueEffect. Unknown names fail.
StatusOr<SimRecording> StudyMachine(char family, const std::string& scenario, uint64_t seed,
                                    int days = 0);

// A study machine searched as the studies search it (axis Y, the server's
// default held-out runs) and scored: what a study needs of one case.
struct StudySearch {
  SimRecording recording;
  EffectSearchInput input;
  std::vector<double> true_drift;  // per row, for the noise floor
  EffectSearchResult result;
  SearchScore score;
};
StatusOr<StudySearch> SearchStudyMachine(char family, const std::string& scenario, uint64_t seed,
                                         int days = 0, const EffectSearchOptions& options = {});

}  // namespace thermocomp
