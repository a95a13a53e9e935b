// Internal: re-parametrising a B-spline surface by chord length without changing its shape (to
// the spline space's approximation error), for the surface fitter's restart. Not part of the
// public API.
#pragma once

#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb::detail {

/// The surface T with the knots, degrees and topology of `surface` whose parameters are spread by
/// mean chord length: T(u', v') ~ S(g_u(u'), g_v(v')), where g_u maps the fraction f of u's domain
/// to the parameter at which the chord length along the u-lines, normalised per line and averaged
/// over lines of constant v, reaches f (and likewise in v). Open directions keep their ends (the
/// boundary stays the boundary); closed ones keep the seam at the same place. T's control points
/// are the least-squares fit to S(g_u(u'), g_v(v')) at 8 x 8 samples per knot cell plus the
/// boundary lines of open directions (QuadraticModel).
///
/// Why: the squared distance to a target does not see how the parameters are spread over the
/// surface (sliding along the target), so a fit whose first steps crowded its parameters (e.g.
/// a torus started with wrong radii: every sensor moves to its own footpoint) relaxes only very
/// slowly; a chord-length spread is close to the one that approximates best (uniform for circles,
/// tori, cylinders) and the fit continues from there.
///
/// A direction whose lines all have zero length (a collapsed surface) keeps its parameters.
/// Deterministic (serial evaluation).
struct Reparametrization {
  BSplineSurface surface;  ///< T
  /// max |g(f) - f| over both directions: how far the chord-length spread is from the surface's
  /// own, as a fraction of the domain (0 = already spread by chord length).
  double shift = 0.0;
};
Reparametrization chordLengthReparametrized(const BSplineSurface& surface);

}  // namespace d2vdb::detail
