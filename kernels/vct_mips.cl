/* Voxel mip propagation (voxel cone tracing), one launch per level; parent
 * voxel p of a level with edge ep = 1 << ep_log2 has children 2x..2x+1,
 * 2y..2y+1, 2z..2z+1 at the finer level (edge 2ep). Offsets and strides are
 * in float4 elements (host/shared/voxel_types.h: layout of both volumes).
 *   mip_iso:   parent = the mean of the 8 children, premultiplied. With
 *              radiance premultiplied by opacity this is 002's alpha-weighted
 *              box filter (colour sum(c a) / sum(a), opacity sum(a) / 8),
 *              and opacity stays separate from colour: an opaque black child
 *              adds opacity, an empty one does not.
 *   mip_aniso: per direction of travel d (+X, -X, +Y, -Y, +Z, -Z), each of
 *              the 4 child pairs along d's axis composited front to back
 *              (front + (1 - front.a) * back), then the 4 results averaged
 *              (Crassin 2011). Children: direction d of the finer anisotropic
 *              level, or, for level 1, isotropic level 0 (src_dir_stride 0).
 * Shapes (vct_common.cl): ML_GPU=0 walks a contiguous range of parents per
 * work-item (local size 1); ML_GPU=1 maps one parent to a work-item in groups
 * of WG (consecutive work-items write consecutive parents). Every child is
 * read once per parent and value set (anisotropic level 1: once for all six
 * directions), so local memory would save nothing.
 * FP_CONTRACT is off so the sums and composites round as in the C++ twin
 * (host/vct/VoxelMipsReference.hpp), which the tests compare bit for bit. */
#pragma OPENCL FP_CONTRACT OFF
#include "vct_common.cl"

/* The index of parent p's child (0, 0, 0) in the finer level. */
ML_INLINE uint child_base(uint p, uint ep_log2) {
  const uint mask = (1u << ep_log2) - 1u;
  const uint x = p & mask, y = (p >> ep_log2) & mask, z = p >> (2u * ep_log2);
  const uint ec = 2u << ep_log2;
  return 2u * x + ec * (2u * y + ec * 2u * z);
}

ML_INLINE float4 mean8(__global const float4* c, uint sy, uint sz) {
  return ((c[0] + c[1]) + (c[sy] + c[sy + 1])) + ((c[sz] + c[sz + 1]) + (c[sz + sy] + c[sz + sy + 1]));
}

ML_INLINE float4 over(float4 front, float4 back) { return front + (1.0f - front.w) * back; }

/* A parent's 8 children, k[x + 2y + 4z]. */
ML_INLINE void load8(__global const float4* c, uint sy, uint sz, float4* k) {
  k[0] = c[0];
  k[1] = c[1];
  k[2] = c[sy];
  k[3] = c[sy + 1];
  k[4] = c[sz];
  k[5] = c[sz + 1];
  k[6] = c[sz + sy];
  k[7] = c[sz + sy + 1];
}

/* Direction d of one parent: the 4 pairs along d's axis (bit s of the child
 * index), u and v the other two axes' bits, in the twin's order. */
ML_INLINE float4 aniso_dir(const float4* k, uint d) {
  const uint axis = d >> 1;
  const uint s = 1u << axis;
  const uint u = axis == 0 ? 2u : 1u;
  const uint v = axis == 2 ? 2u : 4u;
  const uint f = (d & 1u) ? s : 0u; /* -axis travel meets the high child first */
  const uint b = s - f;
  const float4 p0 = over(k[f], k[b]);
  const float4 p1 = over(k[u + f], k[u + b]);
  const float4 p2 = over(k[v + f], k[v + b]);
  const float4 p3 = over(k[u + v + f], k[u + v + b]);
  return ((p0 + p1) + (p2 + p3)) * 0.25f;
}

__kernel VCT_ATTR void mip_iso(__global float4* vol, uint src_off, uint dst_off, uint ep_log2, uint n, uint chunk) {
  uint b, e;
  item_range(n, chunk, &b, &e);
  const uint ec = 2u << ep_log2;
  for (uint p = b; p < e; ++p)
    vol[dst_off + p] = mean8(vol + src_off + child_base(p, ep_log2), ec, ec * ec) * 0.125f;
}

__kernel VCT_ATTR void mip_aniso(__global const float4* src, uint src_off, uint src_dir_stride,
                                 __global float4* dst, uint dst_off, uint ep_log2, uint n, uint chunk) {
  uint b, e;
  item_range(n, chunk, &b, &e);
  const uint ec = 2u << ep_log2;
  for (uint p = b; p < e; ++p) {
    __global const float4* c = src + src_off + child_base(p, ep_log2);
    float4 k[8];
    if (src_dir_stride == 0u) load8(c, ec, ec * ec, k); /* level 1: one set of children for all */
#pragma unroll
    for (uint d = 0; d < 6u; ++d) {
      if (src_dir_stride != 0u) load8(c + d * src_dir_stride, ec, ec * ec, k);
      dst[dst_off + d * n + p] = aniso_dir(k, d);
    }
  }
}
