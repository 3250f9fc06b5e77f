/* The empty-space distance volume of a level-0 voxel grid, declared once for
 * C++ (namespace ml::gpu) and OpenCL C: what the voxel-shadow march
 * (kernels/vct/vct_inject.cl) reads to skip empty space, built by
 * kernels/vct/vct_occupancy.cl (twin: host/vct/OccupancyTwin.hpp).
 *
 * One uchar per voxel of the edge^3 grid, x fastest (x + e * (y + e * z)):
 * the Chebyshev (L-infinity) distance in voxels from the voxel to the nearest
 * filled voxel (VoxelAccum count non-zero), clamped to ML_OCC_MAX_DISTANCE;
 * 0 for a filled voxel. So a value d >= 1 says that every voxel of the cube
 * of half-width d - 1 centred on it is empty (voxels outside the grid count
 * as empty). Any edge from 1 to ML_VOXEL_MAX_EDGE works (the grid's is a
 * power of two). Built in three separable passes (x, y, z), exact for the
 * L-infinity metric: d(v) = min over u of max(|x - ux|, d_yz(u)) and so on. */
#ifndef MANYLIGHTS_VOXEL_OCCUPANCY_H
#define MANYLIGHTS_VOXEL_OCCUPANCY_H

/* The clamp: the march skips up to a cube of half-width 15 voxels at once;
 * the build's passes cost up to 2 * 15 reads per voxel in empty space. */
#define ML_OCC_MAX_DISTANCE 16u

#endif
