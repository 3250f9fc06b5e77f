#include "host/compute/Scan.hpp"

namespace ml::compute {

using detail::ceilDiv;
using detail::u32;

Scanner::Scanner(ClRuntime& rt, const Options& options) : Scanner(ComputeEnv(rt), options) {}

Scanner::Scanner(const ComputeEnv& env, const Options& options) : env_(env), tuning_(resolveTuning(env, options)) {
  const FittedProgram p = buildFitted(env_, tuning_, "compute/scan.cl", "scan");
  if (tuning_.gpu()) tuning_.wg = p.wg;
  reduce_ = cl::Kernel(p.program, "scan_reduce");
  tiles_ = cl::Kernel(p.program, "scan_tiles");
  dummy_ = cl::Buffer(env_.context(), CL_MEM_READ_WRITE, 16);
}

void Scanner::scan(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n, ScanKind kind,
                   cl::Buffer* total, std::size_t total_index, ClPassTimer* timer) {
  detail::checkCount(n, "Scanner::scan");
  detail::checkBuffer(in, n * 4, "Scanner::scan in");
  detail::checkBuffer(out, n * 4, "Scanner::scan out");
  if (total) detail::checkBuffer(*total, (total_index + 1) * 4, "Scanner::scan total");
  if (n == 0) {
    if (total) q.enqueueFillBuffer(*total, cl_uint(0), total_index * 4, 4);
    return;
  }
  level(q, in, out, n, kind == ScanKind::Inclusive, 0, total, total_index, timer);
}

void Scanner::level(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n, bool inclusive,
                    std::size_t depth, cl::Buffer* total, std::size_t total_index, ClPassTimer* timer) {
  const bool gpu = tuning_.gpu();
  const std::size_t local = gpu ? tuning_.wg : 1;
  const std::size_t tile = gpu ? tuning_.wg * tuning_.items : tuning_.cpuChunk(n);
  const std::size_t groups = ceilDiv(n, tile);
  const cl::Buffer& total_buf = total ? *total : dummy_;

  if (groups == 1) {
    detail::setArgs(tiles_, in, out, u32(n), u32(tile), dummy_, cl_uint(0), cl_uint(inclusive), total_buf,
                    u32(total_index), cl_uint(total != nullptr));
    detail::launch(q, tiles_, local, local, timer, "scan.tiles");
    return;
  }
  if (partials_.size() <= depth) partials_.resize(depth + 1);
  // Scratch for this level; deeper levels use their own, so a reference stays
  // valid across the recursive call.
  cl::Buffer partials = partials_[depth].ensure(env_, groups * 4);
  detail::setArgs(reduce_, in, partials, u32(n), u32(tile));
  detail::launch(q, reduce_, groups * local, local, timer, "scan.reduce");
  level(q, partials, partials, groups, false, depth + 1, total, total_index, timer);
  detail::setArgs(tiles_, in, out, u32(n), u32(tile), partials, cl_uint(1), cl_uint(inclusive), dummy_,
                  cl_uint(0), cl_uint(0));
  detail::launch(q, tiles_, groups * local, local, timer, "scan.tiles");
}

std::uint32_t Scanner::exclusiveTotal(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n,
                                      ClPassTimer* timer) {
  cl::Buffer& t = total_.ensure(env_, 4);
  scan(q, in, out, n, ScanKind::Exclusive, &t, 0, timer);
  cl_uint value = 0;
  q.enqueueReadBuffer(t, CL_TRUE, 0, 4, &value);
  return value;
}

void exclusive_scan(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n) {
  auto s = detail::sharedFor<Scanner>(q);
  s.obj.exclusive(q, in, out, n);
}

void inclusive_scan(cl::CommandQueue& q, const cl::Buffer& in, cl::Buffer& out, std::size_t n) {
  auto s = detail::sharedFor<Scanner>(q);
  s.obj.inclusive(q, in, out, n);
}

}  // namespace ml::compute
