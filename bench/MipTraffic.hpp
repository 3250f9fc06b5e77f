#pragma once
// Bytes the voxel mips (kernels/vct/vct_mips.cl) read and write for a grid of
// `edge`^3 voxels and `levels` levels: per parent voxel of level l >= 1, its 8
// children's 16-byte texels (6 direction sets from an anisotropic level 2 up,
// one set below) read and its own 1 or 6 written. The bandwidth figure of the
// VCT and kernel benches.
namespace ml::bench {

inline double mipTrafficBytes(unsigned edge, unsigned levels, bool aniso) {
  double bytes = 0;
  for (unsigned l = 1; l < levels; ++l) {
    const double n = double(edge >> l) * double(edge >> l) * double(edge >> l);
    const double sets = aniso ? 6 : 1, read_sets = aniso && l > 1 ? 6 : 1;
    bytes += 16 * n * (8 * read_sets + sets);
  }
  return bytes;
}

}  // namespace ml::bench
