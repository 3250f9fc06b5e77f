/* Bitonic sort of uint keys (uint values alongside when has_values), any n,
 * in place; see prim_bitonic_network.cl for the network and the implicit padding.
 * The host runs, with C the block a work-item (CPU) or work-group (GPU) sorts
 * in fast memory:
 *   bitonic_block_sort            every C-block sorted (all sizes <= C);
 *   for size = 2C .. next_pow2(n):
 *     bitonic_global_stage(2)     the flip stage, then half-cleaners j >= C,
 *                                 one launch each (they cross blocks); on
 *                                 CPUs two stages per launch where both
 *                                 cross blocks (bitonic_global_stage2);
 *     bitonic_block_merge         the half-cleaners j < C inside each block.
 * CPU: C = `block` elements per work-item, sorted in place in global memory
 * (cache-resident). GPU: C = 2 * WG, in local memory. The global stage's
 * comparator t maps to indices through its half-run length h. */
#include "compute/prim_bitonic_network.cl"

#if !ML_GPU

__kernel void bitonic_block_sort(__global uint* keys, __global uint* vals, uint has_values, uint n, uint block) {
  const uint b = chunk_begin(get_global_id(0), block, n), e = chunk_begin(get_global_id(0) + 1, block, n);
  if (has_values)
    bitonic_sort_range(keys + b, vals + b, 1, e - b);
  else
    bitonic_sort_range(keys + b, vals, 0, e - b);
}

__kernel void bitonic_block_merge(__global uint* keys, __global uint* vals, uint has_values, uint n, uint block) {
  const uint b = chunk_begin(get_global_id(0), block, n), e = chunk_begin(get_global_id(0) + 1, block, n);
  if (has_values)
    bitonic_merge_range(keys + b, vals + b, 1, e - b, block >> 1);
  else
    bitonic_merge_range(keys + b, vals, 0, e - b, block >> 1);
}

/* Work-item g takes comparators [g * per_item, (g + 1) * per_item): whole or
 * partial runs of h consecutive lower indices, processed 8 wide. */
ML_INLINE void global_stage(__global uint* keys, __global uint* vals, const int hv, uint n, uint h, uint flip,
                            uint t0, uint t1) {
  for (uint t = t0; t < t1;) {
    const uint off = t % h;
    const uint cnt = min(h - off, t1 - t);
    const uint base = (t / h) * 2 * h;
    const uint a = base + off;
    if (flip) {
      const uint b = base + 2 * h - 1 - off;
      const uint i0 = b >= n ? b - n + 1 : 0; /* skip partners past n */
      if (i0 < cnt) cx_flip_run(keys, vals, hv, a + i0, b - i0, cnt - i0);
    } else {
      const uint b = a + h;
      if (b < n) cx_run(keys, vals, hv, a, b, min(cnt, n - b));
    }
    t += cnt;
  }
}

__kernel void bitonic_global_stage(__global uint* keys, __global uint* vals, uint has_values, uint n, uint h,
                                   uint flip, uint per_item, uint pairs) {
  const uint t0 = min((uint)get_global_id(0) * per_item, pairs), t1 = min(t0 + per_item, pairs);
  if (has_values)
    global_stage(keys, vals, 1, n, h, flip, t0, t1);
  else
    global_stage(keys, vals, 0, n, h, flip, t0, t1);
}

/* Two stages in one sweep: the flip stage of block size 2h (flip) or the
 * half-cleaner h, followed by the half-cleaner h / 2. Quad u (of N / 4) is
 * closed under both: lower indices a, a + h/2 and their stage-one partners
 * (a + h, a + 3h/2, or for the flip 2h-1-a, 3h/2-1-a within the block). Each
 * work-item takes quads [u0, u1), runs of up to h / 2 consecutive ones, 8 wide
 * where all four rows lie below n, else one by one with the skips. */
ML_INLINE void quad_scalar(__global uint* k, __global uint* v, const int hv, uint n, uint a, uint b, uint c,
                           uint d) {
  /* stage one: (a, c), (b, d); stage two: (a, b), (min(c, d), max(c, d)) */
  if (c < n) cx(k, v, hv, a, c);
  if (d < n) cx(k, v, hv, b, d);
  if (b < n) cx(k, v, hv, a, b);
  const uint lo = min(c, d), hi = max(c, d);
  if (hi < n) cx(k, v, hv, lo, hi);
}

ML_INLINE void global_stage_pair(__global uint* k, __global uint* v, const int hv, uint n, uint h, uint flip,
                                 uint u0, uint u1) {
  const uint q = h >> 1;
  for (uint u = u0; u < u1;) {
    const uint off = u % q;
    const uint cnt = min(q - off, u1 - u);
    const uint base = (u / q) * 2 * h;
    const uint a = base + off;
    /* Highest index touched by this run: the top of its block (flip) or of its upper row. */
    const uint top = flip ? base + 2 * h - 1 - off : a + h + q + cnt - 1;
    uint i = 0;
    if (top < n) {
      for (; i + 8 <= cnt; i += 8) {
        const uint ai = a + i, bi = ai + q;
        /* stage-one partners of ai.. and bi..: ascending rows for the
         * half-cleaner, reversed rows ending at the block top for the flip */
        const uint ci = flip ? base + 2 * h - 8 - off - i : ai + h;
        const uint di = flip ? ci - q : bi + h;
        uint8 ka = vload8(0, k + ai), kb = vload8(0, k + bi), kc = vload8(0, k + ci), kd = vload8(0, k + di);
        uint8 va = (uint8)(0u), vb = va, vc = va, vd = va;
        if (hv) {
          va = vload8(0, v + ai);
          vb = vload8(0, v + bi);
          vc = vload8(0, v + ci);
          vd = vload8(0, v + di);
        }
        if (flip) {
          kc = kc.s76543210;
          kd = kd.s76543210;
          vc = vc.s76543210;
          vd = vd.s76543210;
        }
        cx8(&ka, &kc, &va, &vc, hv);
        cx8(&kb, &kd, &vb, &vd, hv);
        cx8(&ka, &kb, &va, &vb, hv);
        if (flip) /* upper rows: d holds the lower indices now */
          cx8(&kd, &kc, &vd, &vc, hv);
        else
          cx8(&kc, &kd, &vc, &vd, hv);
        if (flip) {
          kc = kc.s76543210;
          kd = kd.s76543210;
          vc = vc.s76543210;
          vd = vd.s76543210;
        }
        vstore8(ka, 0, k + ai);
        vstore8(kb, 0, k + bi);
        vstore8(kc, 0, k + ci);
        vstore8(kd, 0, k + di);
        if (hv) {
          vstore8(va, 0, v + ai);
          vstore8(vb, 0, v + bi);
          vstore8(vc, 0, v + ci);
          vstore8(vd, 0, v + di);
        }
      }
    }
    for (; i < cnt; ++i) {
      const uint ai = a + i, bi = ai + q;
      const uint ci = flip ? base + 2 * h - 1 - off - i : ai + h;
      const uint di = flip ? ci - q : bi + h;
      quad_scalar(k, v, hv, n, ai, bi, ci, di);
    }
    u += cnt;
  }
}

__kernel void bitonic_global_stage2(__global uint* keys, __global uint* vals, uint has_values, uint n, uint h,
                                    uint flip, uint per_item, uint quads) {
  const uint u0 = min((uint)get_global_id(0) * per_item, quads), u1 = min(u0 + per_item, quads);
  if (has_values)
    global_stage_pair(keys, vals, 1, n, h, flip, u0, u1);
  else
    global_stage_pair(keys, vals, 0, n, h, flip, u0, u1);
}

#else /* GPU */

#define BLOCK (2 * WG)

ML_INLINE void load_block(__global const uint* keys, __global const uint* vals, const int hv, uint n, __local uint* lk,
                       __local uint* lv) {
  const uint base = get_group_id(0) * BLOCK;
  for (uint i = get_local_id(0); i < BLOCK; i += WG) {
    const uint gi = base + i;
    lk[i] = gi < n ? keys[gi] : UINT_MAX; /* the padding: maximum keys */
    if (hv) lv[i] = gi < n ? vals[gi] : 0u;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
}

ML_INLINE void store_block(__global uint* keys, __global uint* vals, const int hv, uint n, __local const uint* lk,
                        __local const uint* lv) {
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint base = get_group_id(0) * BLOCK;
  for (uint i = get_local_id(0); i < BLOCK; i += WG) {
    const uint gi = base + i;
    if (gi < n) {
      keys[gi] = lk[i];
      if (hv) vals[gi] = lv[i];
    }
  }
}

/* Half-cleaners j = from .. 1 on the local block; one comparator per work-item. */
ML_INLINE void local_half_stages(__local uint* lk, __local uint* lv, const int hv, uint from) {
  const uint t = get_local_id(0);
  for (uint j = from; j > 0; j >>= 1) {
    uint b;
    const uint a = stage_pair(t, j, 0, &b);
    lcx(lk, lv, hv, a, b);
    barrier(CLK_LOCAL_MEM_FENCE);
  }
}

__kernel WG_ATTR void bitonic_block_sort(__global uint* keys, __global uint* vals, uint has_values, uint n,
                                         uint block) {
  __local uint lk[BLOCK], lv[BLOCK];
  const int hv = has_values != 0;
  load_block(keys, vals, hv, n, lk, lv);
  for (uint size = 2; size <= BLOCK; size <<= 1) {
    uint b;
    const uint a = stage_pair(get_local_id(0), size >> 1, 1, &b);
    lcx(lk, lv, hv, a, b);
    barrier(CLK_LOCAL_MEM_FENCE);
    local_half_stages(lk, lv, hv, size >> 2);
  }
  store_block(keys, vals, hv, n, lk, lv);
}

__kernel WG_ATTR void bitonic_block_merge(__global uint* keys, __global uint* vals, uint has_values, uint n,
                                          uint block) {
  __local uint lk[BLOCK], lv[BLOCK];
  const int hv = has_values != 0;
  load_block(keys, vals, hv, n, lk, lv);
  local_half_stages(lk, lv, hv, BLOCK >> 1);
  store_block(keys, vals, hv, n, lk, lv);
}

/* One comparator per work-item; per_item is unused (always 1). */
__kernel WG_ATTR void bitonic_global_stage(__global uint* keys, __global uint* vals, uint has_values, uint n, uint h,
                                           uint flip, uint per_item, uint pairs) {
  const uint t = get_global_id(0);
  if (t >= pairs) return;
  uint b;
  const uint a = stage_pair(t, h, flip, &b);
  if (b < n) gcx(keys, vals, has_values != 0, a, b);
}

#endif
