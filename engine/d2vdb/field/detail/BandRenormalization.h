// The last two steps of a mesh level set, run after its signs are final.
#pragma once

#include <openvdb/openvdb.h>

namespace d2vdb::detail {

/// One renormalisation step of the band, as openvdb::tools::meshToVolume does by default: the
/// active values are shifted by -0.8 voxel, each takes one Godunov upwind step of the
/// reinitialisation equation phi_t = S(phi)(1 - |grad phi|) with time step one voxel (Sussman,
/// Smereka, Osher, J. Comput. Phys. 114, 1994; Godunov's norm as in Peng, Merriman, Osher, Zhao,
/// Kang, J. Comput. Phys. 155, 1999), keeps the smaller of the stepped and the shifted value, and
/// is shifted back (less 1e-7). This smooths the band's outer layers, where meshToVolume's
/// distances are to nearby triangles rather than the nearest, and only ever lowers values.
/// Unlike meshToVolume's, voxels less than a voxel from the surface keep their values: they are
/// exact distances there, and the step could carry a small value across zero (meshToVolume's
/// renormalisation flips the sign of some surface voxels that way). A value of at least one voxel
/// cannot change sign: shifted it is >= 0.2 voxel (lowered by at most itself) or <= -1.8 voxels
/// (only ever lowered).
/// Reads neighbours through the tree (inactive ones at +-background); deterministic.
void renormalizeBand(openvdb::FloatGrid& grid);

/// Deactivates active values outside (-background, background) (setting them to -+background)
/// and prunes, as meshToVolume does for bands narrower than 4 voxels.
void trimBand(openvdb::FloatGrid& grid);

}  // namespace d2vdb::detail
