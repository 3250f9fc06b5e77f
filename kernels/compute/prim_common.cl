/* Helpers shared by the primitive kernels (scan, compact, reduce, sorts).
 * Built with ML_GPU=0 (CPU-chunked shape: local size 1, each work-item walks a
 * contiguous chunk) or ML_GPU=1 with WG (work-group size) and ITEMS (elements
 * per work-item in a tile). */
#ifndef PRIM_COMMON_CL
#define PRIM_COMMON_CL

/* PoCL's LLVM leaves `inline` helpers out of line when they are large, and
 * then the literal `hv` / `op` / `full` flags they take are runtime branches in
 * the hot loops; force inlining so those fold. */
#define ML_INLINE inline __attribute__((always_inline))

#ifndef ML_GPU
#error "ML_GPU must be defined (0: CPU-chunked kernels, 1: work-group kernels)"
#endif

/* [begin, end) of chunk g. The products are formed in 64 bits because the last
 * chunk's nominal end may pass 2^32 even though n does not. */
ML_INLINE uint chunk_begin(uint g, uint chunk, uint n) { return (uint)min((ulong)g * chunk, (ulong)n); }

ML_INLINE uint next_pow2_u(uint v) {
  uint p = 1;
  while (p < v) p <<= 1;
  return p;
}

#if ML_GPU
#define WG_ATTR __attribute__((reqd_work_group_size(WG, 1, 1)))
/* Elements of a work-group's tile (scan, compact, radix sort: ITEMS each). */
#define TILE (WG * ITEMS)

/* Exclusive prefix sum of one value per work-item over the work-group
 * (Hillis-Steele in local memory); *total receives the sum of all values. Every
 * work-item of the group must call it (it contains barriers). */
ML_INLINE uint wg_exclusive_scan(uint v, __local uint* tmp, uint* total) {
  const uint lid = get_local_id(0);
  tmp[lid] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint off = 1; off < WG; off <<= 1) {
    const uint add = lid >= off ? tmp[lid - off] : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    tmp[lid] += add;
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const uint inclusive = tmp[lid];
  *total = tmp[WG - 1];
  /* The next call writes tmp again; nobody may still be reading it. */
  barrier(CLK_LOCAL_MEM_FENCE);
  return inclusive - v;
}
#endif

#endif /* PRIM_COMMON_CL */
