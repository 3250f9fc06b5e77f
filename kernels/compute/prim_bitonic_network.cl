/* Include-only (no __kernel): bitonic compare-exchange networks shared by bitonic_sort.cl and
 * segmented_sort.cl.
 *
 * The network is the "flip" form: merging blocks of `size` first compares
 * i with size - 1 - i inside each block, then runs half-cleaners (i with
 * i + j) for j = size / 4 .. 1. Every comparator puts the minimum at the lower
 * index, so every block comes out ascending and no direction bits are needed.
 * Any length works with no padding buffer: positions >= len act as keys of
 * the maximum value, and a comparator whose upper index is >= len would leave
 * both elements where they are, so it is skipped. (The work-group kernels pad
 * their local tiles with UINT_MAX literally; since swaps need a strictly
 * greater key, padding never moves and real maximum keys never go past it.)
 *
 * `hv` (has values) is a literal at every call site, so the value moves fold
 * away for key-only sorts. */
#ifndef PRIM_BITONIC_CL
#define PRIM_BITONIC_CL

#include "compute/prim_common.cl"

#if !ML_GPU

ML_INLINE void cx(__global uint* k, __global uint* v, const int hv, uint a, uint b) {
  const uint ka = k[a], kb = k[b];
  k[a] = min(ka, kb);
  k[b] = max(ka, kb);
  if (hv) {
    const uint va = v[a], vb = v[b];
    const int swap = ka > kb;
    v[a] = swap ? vb : va;
    v[b] = swap ? va : vb;
  }
}

/* Comparators (a + i, b + i), i < cnt, 8 at a time: branch-free min / max. */
ML_INLINE void cx_run(__global uint* k, __global uint* v, const int hv, uint a, uint b, uint cnt) {
  uint i = 0;
  for (; i + 8 <= cnt; i += 8) {
    const uint8 ka = vload8(0, k + a + i), kb = vload8(0, k + b + i);
    vstore8(min(ka, kb), 0, k + a + i);
    vstore8(max(ka, kb), 0, k + b + i);
    if (hv) {
      const int8 swap = ka > kb;
      const uint8 va = vload8(0, v + a + i), vb = vload8(0, v + b + i);
      vstore8(select(va, vb, swap), 0, v + a + i);
      vstore8(select(vb, va, swap), 0, v + b + i);
    }
  }
  for (; i < cnt; ++i) cx(k, v, hv, a + i, b + i);
}

/* Comparators (a + i, b - i), i < cnt: the flip stage, the upper run reversed. */
ML_INLINE void cx_flip_run(__global uint* k, __global uint* v, const int hv, uint a, uint b, uint cnt) {
  uint i = 0;
  for (; i + 8 <= cnt; i += 8) {
    const uint8 ka = vload8(0, k + a + i);
    const uint8 kb = vload8(0, k + b - i - 7).s76543210;
    vstore8(min(ka, kb), 0, k + a + i);
    vstore8(max(ka, kb).s76543210, 0, k + b - i - 7);
    if (hv) {
      const int8 swap = ka > kb;
      const uint8 va = vload8(0, v + a + i), vb = vload8(0, v + b - i - 7).s76543210;
      vstore8(select(va, vb, swap), 0, v + a + i);
      vstore8(select(vb, va, swap).s76543210, 0, v + b - i - 7);
    }
  }
  for (; i < cnt; ++i) cx(k, v, hv, a + i, b - i);
}

/* One half-cleaner stage (distance j) over [0, len), in blocks of 2j. */
ML_INLINE void half_stage(__global uint* k, __global uint* v, const int hv, uint len, uint j) {
  for (uint base = 0; base + j < len; base += 2 * j) cx_run(k, v, hv, base, base + j, min(j, len - base - j));
}

/* The flip stage of block size `size` over [0, len). */
ML_INLINE void flip_stage(__global uint* k, __global uint* v, const int hv, uint len, uint size) {
  const uint h = size >> 1;
  for (uint base = 0; base + h < len; base += size) {
    const uint top = base + size - 1;
    const uint i0 = top >= len ? top - len + 1 : 0; /* first comparator whose upper index is < len */
    cx_flip_run(k, v, hv, base + i0, top - i0, h - i0);
  }
}

/* Stages with distance < 8 stay inside aligned groups of 8 elements: they run
 * in registers, several stages per load / store, instead of as scalar
 * compare-exchanges over memory. cx4 compares lanes of a with lanes of b. */
ML_INLINE void cx4(uint4* a, uint4* b, uint4* va, uint4* vb, const int hv) {
  const uint4 ka = *a, kb = *b;
  *a = min(ka, kb);
  *b = max(ka, kb);
  if (hv) {
    const int4 swap = ka > kb;
    const uint4 x = *va, y = *vb;
    *va = select(x, y, swap);
    *vb = select(y, x, swap);
  }
}

/* Half-cleaner j = 4, 2 or 1 / flip stage of size 8 or 4 on one group. */
ML_INLINE void group_half4(uint8* k, uint8* v, const int hv) {
  uint4 a = (*k).lo, b = (*k).hi, va = (*v).lo, vb = (*v).hi;
  cx4(&a, &b, &va, &vb, hv);
  *k = (uint8)(a, b);
  *v = (uint8)(va, vb);
}
ML_INLINE void group_half2(uint8* k, uint8* v, const int hv) {
  uint4 a = (*k).s0145, b = (*k).s2367, va = (*v).s0145, vb = (*v).s2367;
  cx4(&a, &b, &va, &vb, hv);
  *k = (uint8)(a.s01, b.s01, a.s23, b.s23);
  *v = (uint8)(va.s01, vb.s01, va.s23, vb.s23);
}
ML_INLINE void group_half1(uint8* k, uint8* v, const int hv) {
  uint4 a = (*k).s0246, b = (*k).s1357, va = (*v).s0246, vb = (*v).s1357;
  cx4(&a, &b, &va, &vb, hv);
  *k = (uint8)(a.s0, b.s0, a.s1, b.s1, a.s2, b.s2, a.s3, b.s3);
  *v = (uint8)(va.s0, vb.s0, va.s1, vb.s1, va.s2, vb.s2, va.s3, vb.s3);
}
ML_INLINE void group_flip4(uint8* k, uint8* v, const int hv) {
  uint4 a = (*k).s0145, b = (*k).s3276, va = (*v).s0145, vb = (*v).s3276;
  cx4(&a, &b, &va, &vb, hv);
  *k = (uint8)(a.s01, b.s10, a.s23, b.s32);
  *v = (uint8)(va.s01, vb.s10, va.s23, vb.s32);
}
ML_INLINE void group_flip8(uint8* k, uint8* v, const int hv) {
  uint4 a = (*k).lo, b = (*k).s7654, va = (*v).lo, vb = (*v).s7654;
  cx4(&a, &b, &va, &vb, hv);
  *k = (uint8)(a, b.s3210);
  *v = (uint8)(va, vb.s3210);
}

/* full: the complete network of sizes 2, 4, 8 (sorts the group); else the
 * closing half-cleaners 4, 2, 1 of a larger merge. */
ML_INLINE void group_stages(uint8* k, uint8* v, const int hv, const int full) {
  if (full) {
    group_half1(k, v, hv); /* the flip stage of size 2 is the j = 1 half-cleaner */
    group_flip4(k, v, hv);
    group_half1(k, v, hv);
    group_flip8(k, v, hv);
  } else {
    group_half4(k, v, hv);
  }
  group_half2(k, v, hv);
  group_half1(k, v, hv);
}

/* group_stages on every aligned group of 8 in [0, len). The last, partial
 * group is padded in registers with maximum keys, which stay in the padded
 * lanes (a swap needs a strictly greater key). */
ML_INLINE void groups_of_8(__global uint* k, __global uint* v, const int hv, uint len, const int full) {
  uint g = 0;
  for (; g + 8 <= len; g += 8) {
    uint8 x = vload8(0, k + g), y = hv ? vload8(0, v + g) : (uint8)(0u);
    group_stages(&x, &y, hv, full);
    vstore8(x, 0, k + g);
    if (hv) vstore8(y, 0, v + g);
  }
  const uint rem = len - g;
  if (rem > 1) {
    uint xs[8], ys[8];
    for (uint i = 0; i < 8; ++i) {
      xs[i] = i < rem ? k[g + i] : UINT_MAX;
      ys[i] = (hv && i < rem) ? v[g + i] : 0u;
    }
    uint8 x = vload8(0, xs), y = vload8(0, ys);
    group_stages(&x, &y, hv, full);
    vstore8(x, 0, xs);
    vstore8(y, 0, ys);
    for (uint i = 0; i < rem; ++i) {
      k[g + i] = xs[i];
      if (hv) v[g + i] = ys[i];
    }
  }
}

/* Two consecutive half-cleaners, j and j / 2 (j >= 16), in one sweep: each
 * block of 2j is self-contained for both, so four 8-wide rows are loaded once,
 * compared twice and stored once (half the memory traffic of two sweeps). The
 * block that straddles len, if any, runs the two stages separately. */
ML_INLINE void cx8(uint8* a, uint8* b, uint8* va, uint8* vb, const int hv) {
  const uint8 ka = *a, kb = *b;
  *a = min(ka, kb);
  *b = max(ka, kb);
  if (hv) {
    const int8 swap = ka > kb;
    const uint8 x = *va, y = *vb;
    *va = select(x, y, swap);
    *vb = select(y, x, swap);
  }
}

ML_INLINE void half_stage_pair(__global uint* k, __global uint* v, const int hv, uint len, uint j) {
  const uint q = j >> 1;
  uint base = 0;
  for (; base + 2 * j <= len; base += 2 * j) {
    for (uint i = base; i < base + q; i += 8) {
      uint8 a = vload8(0, k + i), b = vload8(0, k + i + q), c = vload8(0, k + i + j), d = vload8(0, k + i + j + q);
      uint8 va = (uint8)(0u), vb = va, vc = va, vd = va;
      if (hv) {
        va = vload8(0, v + i);
        vb = vload8(0, v + i + q);
        vc = vload8(0, v + i + j);
        vd = vload8(0, v + i + j + q);
      }
      cx8(&a, &c, &va, &vc, hv);
      cx8(&b, &d, &vb, &vd, hv);
      cx8(&a, &b, &va, &vb, hv);
      cx8(&c, &d, &vc, &vd, hv);
      vstore8(a, 0, k + i);
      vstore8(b, 0, k + i + q);
      vstore8(c, 0, k + i + j);
      vstore8(d, 0, k + i + j + q);
      if (hv) {
        vstore8(va, 0, v + i);
        vstore8(vb, 0, v + i + q);
        vstore8(vc, 0, v + i + j);
        vstore8(vd, 0, v + i + j + q);
      }
    }
  }
  if (base < len) {
    __global uint* vb = hv ? v + base : v;
    half_stage(k + base, vb, hv, len - base, j);
    half_stage(k + base, vb, hv, len - base, q);
  }
}

/* The half-cleaners j = from .. 8, two at a time where possible. */
ML_INLINE void half_stages_down_to_8(__global uint* k, __global uint* v, const int hv, uint len, uint from) {
  uint j = from;
  for (; j >= 16; j >>= 2) half_stage_pair(k, v, hv, len, j);
  if (j == 8) half_stage(k, v, hv, len, 8);
}

/* Sorts k[0, len) ascending (v alongside), in place. */
ML_INLINE void bitonic_sort_range(__global uint* k, __global uint* v, const int hv, uint len) {
  const uint np = next_pow2_u(len);
  groups_of_8(k, v, hv, len, 1);
  for (uint size = 16; size <= np; size <<= 1) {
    flip_stage(k, v, hv, len, size);
    half_stages_down_to_8(k, v, hv, len, size >> 2);
    groups_of_8(k, v, hv, len, 0);
  }
}

/* The half-cleaners j = from .. 1 (from >= 8) over [0, len): the tail of a
 * merge whose larger stages were done by others. */
ML_INLINE void bitonic_merge_range(__global uint* k, __global uint* v, const int hv, uint len, uint from) {
  half_stages_down_to_8(k, v, hv, len, from);
  groups_of_8(k, v, hv, len, 0);
}

#else /* GPU helpers: local-memory compare-exchange */

ML_INLINE void lcx(__local uint* k, __local uint* v, const int hv, uint a, uint b) {
  const uint ka = k[a], kb = k[b];
  if (ka > kb) {
    k[a] = kb;
    k[b] = ka;
    if (hv) {
      const uint t = v[a];
      v[a] = v[b];
      v[b] = t;
    }
  }
}

ML_INLINE void gcx(__global uint* k, __global uint* v, const int hv, uint a, uint b) {
  const uint ka = k[a], kb = k[b];
  if (ka > kb) {
    k[a] = kb;
    k[b] = ka;
    if (hv) {
      const uint t = v[a];
      v[a] = v[b];
      v[b] = t;
    }
  }
}

/* Comparator t of a stage: half-run length h (size / 2 for flip stages, j for
 * half-cleaners; a power of two). Returns the lower index, *b the upper. Masks
 * rather than t / h and t % h: integer division is slow on GPUs, and LLVM
 * pairs the two into a `freeze` instruction that Oclgrind cannot simulate. */
ML_INLINE uint stage_pair(uint t, uint h, int flip, uint* b) {
  const uint off = t & (h - 1), base = (t - off) * 2;
  *b = flip ? base + 2 * h - 1 - off : base + off + h;
  return base + off;
}

#endif

#endif /* PRIM_BITONIC_CL */
