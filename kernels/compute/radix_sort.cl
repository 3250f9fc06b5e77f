/* LSD radix sort passes, reduce-then-scan (no work-group waits on another):
 *   radix_hist:    per-chunk (CPU) / per-work-group (GPU) digit counts, stored
 *                  digit-major: counts[digit * groups + group];
 *   (host)         exclusive scan of counts -> each (digit, group)'s first
 *                  output slot; digit-major order makes the pass stable;
 *   radix_scatter: each chunk / group re-reads its keys and writes them to
 *                  their slots, in input order within a digit.
 * Defines: KEY64 (0: uint keys, 1: ulong keys), RADIX_BITS (digit width,
 * counters per group = 2^RADIX_BITS), ML_GPU, and for ML_GPU: WG, ITEMS.
 * `mask` selects the digit bits of this pass (fewer than RADIX_BITS on the last
 * pass when key_bits is not a multiple). Both shapes take the same arguments:
 * a group owns keys [g * chunk, (g + 1) * chunk). The CPU kernels touch only
 * the mask + 1 counters of the pass (RADIX_BITS is the widest digit; the host
 * scans (mask + 1) * groups counters), so narrower passes do not pay for the
 * widest one's 2^RADIX_BITS counters per chunk. */
#include "compute/prim_common.cl"

#define RADIX (1u << RADIX_BITS)

#if KEY64
typedef ulong KEY_T;
#else
typedef uint KEY_T;
#endif

ML_INLINE uint digit_of(KEY_T key, uint shift, uint mask) { return (uint)(key >> shift) & mask; }

#if !ML_GPU

__kernel void radix_hist(__global const KEY_T* restrict keys, uint n, uint chunk, uint shift, uint mask,
                         __global uint* restrict counts, uint groups) {
  const uint g = get_global_id(0);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  /* Four sub-histograms: runs of equal digits would otherwise serialise on
   * one counter's load-increment-store. */
  uint h0[RADIX], h1[RADIX], h2[RADIX], h3[RADIX];
  for (uint r = 0; r <= mask; ++r) h0[r] = h1[r] = h2[r] = h3[r] = 0;
  uint i = b;
  for (; i + 4 <= e; i += 4) {
    h0[digit_of(keys[i], shift, mask)]++;
    h1[digit_of(keys[i + 1], shift, mask)]++;
    h2[digit_of(keys[i + 2], shift, mask)]++;
    h3[digit_of(keys[i + 3], shift, mask)]++;
  }
  for (; i < e; ++i) h0[digit_of(keys[i], shift, mask)]++;
  for (uint r = 0; r <= mask; ++r) counts[r * groups + g] = h0[r] + h1[r] + h2[r] + h3[r];
}

/* Scatter with software write-combining: each digit's keys are staged in a
 * private, cache-resident line of LINE elements and written out a whole
 * 64-byte line at a time with non-temporal stores where the compiler offers
 * them. 256 digits' worth of scattered single-element stores would otherwise
 * make every store a read-for-ownership of a cold line; full-line streaming
 * stores skip that read and touch each destination page once per line instead
 * of once per key (about 2x on this pass on the 2-core PoCL machine). Only
 * lines that lie entirely inside this chunk's slot range of the digit are
 * streamed; the partial first and last line of each range, which the
 * neighbouring range shares, are written element by element. */
#if KEY64
#define LINE 8 /* keys per 64-byte line */
#define VLOAD_KEYS vload8
#define VSTORE_KEYS vstore8
typedef ulong8 KEY_LINE_T;
typedef uint8 VAL_LINE_T;
#define VLOAD_VALS vload8
#define VSTORE_VALS vstore8
#else
#define LINE 16
#define VLOAD_KEYS vload16
#define VSTORE_KEYS vstore16
typedef uint16 KEY_LINE_T;
typedef uint16 VAL_LINE_T;
#define VLOAD_VALS vload16
#define VSTORE_VALS vstore16
#endif

#if defined(__clang__) && defined(__has_builtin)
#if __has_builtin(__builtin_nontemporal_store)
#define ML_STREAM_STORE(value, ptr) __builtin_nontemporal_store((value), (ptr))
#endif
#endif
#ifndef ML_STREAM_STORE
#define ML_STREAM_STORE(value, ptr) (*(ptr) = (value))
#endif

/* Writes slots [from, to) of digit d's staged line (slot & (LINE - 1) indexes it). */
ML_INLINE void write_partial(__global KEY_T* keys_out, __global uint* vals_out, const int hv, const KEY_T* kline,
                             const uint* vline, uint from, uint to) {
  for (uint p = from; p < to; ++p) {
    keys_out[p] = kline[p & (LINE - 1)];
    if (hv) vals_out[p] = vline[p & (LINE - 1)];
  }
}

ML_INLINE void scatter_chunk(__global const KEY_T* restrict keys_in, __global KEY_T* restrict keys_out,
                             __global const uint* restrict vals_in, __global uint* restrict vals_out, const int hv,
                             uint b, uint e, uint shift, uint mask, __global const uint* restrict offsets, uint g,
                             uint groups) {
  uint pos[RADIX], start[RADIX];
  KEY_T kbuf[RADIX * LINE] __attribute__((aligned(64)));
  uint vbuf[RADIX * LINE] __attribute__((aligned(64)));
  for (uint r = 0; r <= mask; ++r) start[r] = pos[r] = offsets[r * groups + g];
  /* Streaming vector stores need naturally aligned lines; a buffer made from
   * an unaligned host pointer gets plain (unaligned) vector stores instead. */
  const int aligned = (((size_t)keys_out | (hv ? (size_t)vals_out : 0)) & 63) == 0;
  for (uint i = b; i < e; ++i) {
    const KEY_T k = keys_in[i];
    const uint d = digit_of(k, shift, mask);
    const uint p = pos[d]++;
    const uint slot = p & (LINE - 1);
    kbuf[d * LINE + slot] = k;
    if (hv) vbuf[d * LINE + slot] = vals_in[i];
    if (slot == LINE - 1) {
      const uint line = p - (LINE - 1);
      if (line >= start[d] && aligned) {
        ML_STREAM_STORE(VLOAD_KEYS(0, kbuf + d * LINE), (__global KEY_LINE_T*)(keys_out + line));
        if (hv) ML_STREAM_STORE(VLOAD_VALS(0, vbuf + d * LINE), (__global VAL_LINE_T*)(vals_out + line));
      } else if (line >= start[d]) {
        VSTORE_KEYS(VLOAD_KEYS(0, kbuf + d * LINE), 0, keys_out + line);
        if (hv) VSTORE_VALS(VLOAD_VALS(0, vbuf + d * LINE), 0, vals_out + line);
      } else {
        write_partial(keys_out, vals_out, hv, kbuf + d * LINE, vbuf + d * LINE, start[d], p + 1);
      }
    }
  }
  /* The last, partial line of every digit. */
  for (uint r = 0; r <= mask; ++r) {
    const uint end = pos[r];
    if (end & (LINE - 1)) {
      const uint line = end & ~(uint)(LINE - 1);
      write_partial(keys_out, vals_out, hv, kbuf + r * LINE, vbuf + r * LINE, max(line, start[r]), end);
    }
  }
#if defined(__x86_64__) && defined(__has_builtin)
#if __has_builtin(__builtin_ia32_sfence)
  /* Streaming stores are weakly ordered; make them visible before the kernel
   * reports completion. */
  __builtin_ia32_sfence();
#endif
#endif
}

/* Whether every key of chunk g has digit d: its count of d (the gap to the
 * next entry of the digit-major scan; the scan covers mask + 1 digits) is the
 * chunk's length. */
ML_INLINE int chunk_is_one_digit(__global const uint* restrict offsets, uint d, uint g, uint groups, uint mask,
                                 uint n, uint len) {
  const uint at = d * groups + g;
  const uint next = g + 1 < groups || d < mask ? offsets[at + 1] : n;
  return next - offsets[at] == len;
}

__kernel void radix_scatter(__global const KEY_T* restrict keys_in, __global KEY_T* restrict keys_out,
                            __global const uint* restrict vals_in, __global uint* restrict vals_out,
                            uint has_values, uint n, uint chunk, uint shift, uint mask,
                            __global const uint* restrict offsets, uint groups) {
  const uint g = get_global_id(0);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  if (b >= e) return;
  /* A chunk whose keys all share this pass's digit (equal, sorted or
   * narrow-ranged keys, high passes of small keys) moves as one block: a
   * copy instead of a scatter. */
  const uint d0 = digit_of(keys_in[b], shift, mask);
  if (chunk_is_one_digit(offsets, d0, g, groups, mask, n, e - b)) {
    const uint dst = offsets[d0 * groups + g];
    for (uint i = 0; i < e - b; ++i) keys_out[dst + i] = keys_in[b + i];
    if (has_values)
      for (uint i = 0; i < e - b; ++i) vals_out[dst + i] = vals_in[b + i];
    return;
  }
  if (has_values)
    scatter_chunk(keys_in, keys_out, vals_in, vals_out, 1, b, e, shift, mask, offsets, g, groups);
  else
    scatter_chunk(keys_in, keys_out, vals_in, vals_out, 0, b, e, shift, mask, offsets, g, groups);
}

#else /* GPU: a work-group walks its range tile by tile (WG * ITEMS keys) */

__kernel WG_ATTR void radix_hist(__global const KEY_T* keys, uint n, uint chunk, uint shift, uint mask,
                                 __global uint* counts, uint groups) {
  __local uint hist[RADIX];
  const uint lid = get_local_id(0);
  const uint g = get_group_id(0);
  for (uint r = lid; r < RADIX; r += WG) hist[r] = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  for (uint i = b + lid; i < e; i += WG) atomic_inc(&hist[digit_of(keys[i], shift, mask)]);
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint r = lid; r < RADIX; r += WG) counts[r * groups + g] = hist[r];
}

/* Per tile: rank every key among the tile's keys with the same digit (stable
 * local counting sort through an exclusive scan of per-(digit, work-item)
 * counters), reorder the tile in local memory, then write each digit's run to
 * its running global position, so that consecutive work-items write
 * consecutive addresses. */
__kernel WG_ATTR void radix_scatter(__global const KEY_T* keys_in, __global KEY_T* keys_out,
                                    __global const uint* vals_in, __global uint* vals_out, uint has_values,
                                    uint n, uint chunk, uint shift, uint mask, __global const uint* offsets,
                                    uint groups) {
  __local uint cnt[RADIX * WG]; /* cnt[d * WG + lid]: keys of digit d held by work-item lid */
  __local KEY_T skeys[TILE];
  __local uint svals[TILE];
  __local uint run[RADIX];    /* next global slot of each digit for this group */
  __local uint dstart[RADIX]; /* first slot of each digit in the locally sorted tile */
  __local uint tmp[WG];
  const uint lid = get_local_id(0);
  const uint g = get_group_id(0);
  const uint b = chunk_begin(g, chunk, n), e = chunk_begin(g + 1, chunk, n);
  for (uint r = lid; r < RADIX; r += WG) run[r] = offsets[r * groups + g];

  for (uint base = b; base < e; base += TILE) {
    const uint valid = min((uint)TILE, e - base);
    for (uint r = 0; r < RADIX; ++r) cnt[r * WG + lid] = 0;
    /* ITEMS consecutive keys per work-item: work-item order then item order
     * is input order, which the ranking below preserves. Slots past `valid`
     * get the largest digit so they sort behind every real key. */
    KEY_T k[ITEMS];
    uint v[ITEMS], d[ITEMS], before[ITEMS];
    for (uint it = 0; it < ITEMS; ++it) {
      const uint idx = lid * ITEMS + it;
      if (idx < valid) {
        k[it] = keys_in[base + idx];
        v[it] = has_values ? vals_in[base + idx] : 0u;
        d[it] = digit_of(k[it], shift, mask);
      } else {
        k[it] = 0;
        v[it] = 0;
        d[it] = RADIX - 1;
      }
      before[it] = cnt[d[it] * WG + lid];
      cnt[d[it] * WG + lid] = before[it] + 1;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Exclusive scan of cnt in (digit, work-item) order: each work-item scans
     * RADIX consecutive entries after a work-group scan of their sums. */
    uint s = 0;
    for (uint r = 0; r < RADIX; ++r) s += cnt[lid * RADIX + r];
    uint total;
    uint p = wg_exclusive_scan(s, tmp, &total);
    for (uint r = 0; r < RADIX; ++r) {
      const uint c = cnt[lid * RADIX + r];
      cnt[lid * RADIX + r] = p;
      p += c;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint it = 0; it < ITEMS; ++it) {
      const uint slot = cnt[d[it] * WG + lid] + before[it];
      skeys[slot] = k[it];
      svals[slot] = v[it];
    }
    for (uint r = lid; r < RADIX; r += WG) dstart[r] = cnt[r * WG];
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint i = lid; i < valid; i += WG) {
      const KEY_T key = skeys[i];
      const uint dd = digit_of(key, shift, mask);
      const uint dst = run[dd] + (i - dstart[dd]);
      keys_out[dst] = key;
      if (has_values) vals_out[dst] = svals[i];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Only the group's last tile can be partial, so counting its padding
     * into the top digit's run is harmless. */
    for (uint r = lid; r < RADIX; r += WG) run[r] += (r + 1 < RADIX ? dstart[r + 1] : (uint)TILE) - dstart[r];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
}

#endif
