/* Shared by the voxel cone tracing kernels (vct_*.cl): the two kernel shapes
 * over n items (voxels or parent voxels). ML_GPU=0: work-item g walks the
 * contiguous range [g * chunk, (g + 1) * chunk) clamped to n, local size 1;
 * ML_GPU=1: one item per work-item, work-groups of WG (VCT_ATTR). */
#ifndef VCT_COMMON_CL
#define VCT_COMMON_CL
#pragma OPENCL FP_CONTRACT OFF
#include "compute/prim_common.cl"

#if ML_GPU
#define VCT_ATTR WG_ATTR
#else
#define VCT_ATTR
#endif

ML_INLINE void item_range(uint n, uint chunk, uint* b, uint* e) {
#if ML_GPU
  *b = get_global_id(0);
  *e = min(*b + 1u, n);
#else
  *b = chunk_begin(get_global_id(0), chunk, n);
  *e = chunk_begin(get_global_id(0) + 1u, chunk, n);
#endif
}

#endif
