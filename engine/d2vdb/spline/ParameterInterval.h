// A closed parameter interval: the domain of a curve, of one surface direction, or of a segment.
#pragma once

#include <cmath>

namespace d2vdb {

/// The parameter interval [start, end]. Every interval d2vdb returns has start < end (finite).
/// Plain value type; it validates nothing itself.
struct ParameterInterval {
  double start = 0.0;
  double end = 1.0;

  /// end - start.
  double length() const { return end - start; }

  /// True when start <= t <= end (false for NaN).
  bool contains(double t) const { return t >= start && t <= end; }

  /// The parameter at `fraction` of the interval, (1 - fraction) * start + fraction * end; exactly
  /// `start` at 0 and exactly `end` at 1 (no rounding at the ends). Fractions outside [0, 1]
  /// extrapolate linearly.
  double at(double fraction) const { return (1.0 - fraction) * start + fraction * end; }

  /// Reduces t modulo length() into [start, end): the parameter of a periodic curve or surface
  /// direction. `t` must be finite (NaN or infinity give NaN).
  double wrap(double t) const {
    const double period = length();
    double offset = std::fmod(t - start, period);
    if (offset < 0.0) offset += period;
    const double wrapped = start + offset;
    return wrapped >= end ? start : wrapped;  // offset can round up to the full period
  }
};

}  // namespace d2vdb
