// The white noise of a logged channel and what filtering does to it. A
// noisy declared sensor makes any smoothing term look like an effect (a
// short lag of it, or a long lag of a sensor sharing its heat source,
// averages the noise away); these numbers tell that gain apart from
// physics (docs/model.md §9).
#pragma once

#include <cstddef>

#include "model/term_features.h"

namespace thermocomp {

// Standard deviation of the channel's white noise (degC), from its second
// differences x[i+1] - 2x[i] + x[i-1], in which a slowly varying
// temperature cancels and independent noise has variance 6 sigma^2; the
// largest 1 % (steps, gaps) are left out. 0 with fewer than 20 regular
// triples.
double WhiteNoise(const TimeSeries& raw);
// Median interval between samples, minutes (1 without two samples).
double SampleIntervalMin(const TimeSeries& raw);
// Variance of white noise of standard deviation sigma after an EWMA with
// this alpha: sigma^2 * alpha / (2 - alpha).
double FilteredNoiseVariance(double sigma, double alpha);
// What averaging a sensor's noise could remove from the squared error of
// a fit on n points where the sensor's change enters with coefficient beta
// (mm/K), when its filter goes from alpha_from to alpha_to: beta^2 times
// the drop in the filtered noise variance, twice (at the point and at the
// datum), on every point (mm^2). 0 when the variance does not drop.
double NoiseAveragingGain(double beta, double sigma, double alpha_from, double alpha_to, size_t n);
// EWMA alpha at sample interval dt equivalent to a first-order lag tau
// (both minutes): 1 - exp(-dt/tau); 1 for tau 0.
double AlphaFor(double tau_min, double dt_min);
// The lag's time constant of an EWMA alpha at interval dt: -dt / ln(1 - alpha); 0 for alpha 1.
double TauFor(double alpha, double dt_min);

}  // namespace thermocomp
