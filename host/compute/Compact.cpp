#include "host/compute/Compact.hpp"

#include <stdexcept>

namespace ml::compute {

using detail::ceilDiv;
using detail::u32;

Compactor::Compactor(ClRuntime& rt, const Options& options) : Compactor(ComputeEnv(rt), options) {}

Compactor::Compactor(const ComputeEnv& env, const Options& options)
    : env_(env), tuning_(resolveTuning(env, options)), scanner_(env, options) {
  const FittedProgram p = buildFitted(env_, tuning_, "compute/compact.cl", "compact");
  if (tuning_.gpu()) tuning_.wg = p.wg;
  compact_count_ = cl::Kernel(p.program, "compact_count");
  unique_count_ = cl::Kernel(p.program, "unique_count");
  compact_write_ = cl::Kernel(p.program, "compact_write");
  unique_write_ = cl::Kernel(p.program, "unique_write");
}

std::size_t Compactor::run(cl::CommandQueue& q, Mode mode, const cl::Buffer& in, const cl::Buffer& flags,
                           cl::Buffer& out, std::size_t n, ClPassTimer* timer) {
  detail::checkCount(n, "Compactor");
  if (mode != Mode::Indices) detail::checkBuffer(in, n * 4, "Compactor input");
  if (mode != Mode::Unique) detail::checkBuffer(flags, n * 4, "Compactor flags");
  detail::checkBuffer(out, n * 4, "Compactor out");
  if ((mode != Mode::Indices && detail::sameBuffer(in, out)) || (mode != Mode::Unique && detail::sameBuffer(flags, out)))
    throw std::invalid_argument("Compactor: out must not alias the inputs");

  const bool gpu = tuning_.gpu();
  const std::size_t local = gpu ? tuning_.wg : 1;
  const std::size_t chunk = gpu ? tuning_.wg * tuning_.items : tuning_.cpuChunk(n);
  const std::size_t groups = n ? ceilDiv(n, chunk) : 0;
  // counts[0, groups) per chunk, scanned in place; the total lands in
  // counts[groups], which also bounds the last chunk's output range.
  cl::Buffer counts = counts_.ensure(env_, (groups + 1) * 4);
  const bool unique = mode == Mode::Unique;
  cl::Kernel& count = unique ? unique_count_ : compact_count_;
  detail::setArgs(count, unique ? in : flags, u32(n), u32(chunk), counts);
  detail::launch(q, count, groups * local, local, timer, "compact.count");
  scanner_.scan(q, counts, counts, groups, ScanKind::Exclusive, &counts, groups, timer);
  cl::Kernel& write = unique ? unique_write_ : compact_write_;
  if (unique)
    detail::setArgs(write, in, out, u32(n), u32(chunk), counts);
  else  // indices mode reads no input values; flags stands in for the unused argument
    detail::setArgs(write, mode == Mode::Indices ? flags : in, flags, out, u32(n), u32(chunk),
                    cl_uint(mode == Mode::Indices), counts);
  detail::launch(q, write, groups * local, local, timer, "compact.write");
  return groups;
}

std::size_t Compactor::readCount(cl::CommandQueue& q, std::size_t index) {
  cl_uint value = 0;
  q.enqueueReadBuffer(counts_.get(), CL_TRUE, index * 4, 4, &value);
  return value;
}

void Compactor::copyCount(cl::CommandQueue& q, std::size_t index, cl::Buffer& count, std::size_t count_index) {
  detail::checkBuffer(count, (count_index + 1) * 4, "Compactor count");
  q.enqueueCopyBuffer(counts_.get(), count, index * 4, count_index * 4, 4);
}

}  // namespace ml::compute

namespace ml::compute {

std::size_t Compactor::compact(cl::CommandQueue& q, const cl::Buffer& in, const cl::Buffer& flags, cl::Buffer& out,
                               std::size_t n, ClPassTimer* timer) {
  return readCount(q, run(q, Mode::Values, in, flags, out, n, timer));
}

std::size_t Compactor::compactIndices(cl::CommandQueue& q, const cl::Buffer& flags, cl::Buffer& out, std::size_t n,
                                      ClPassTimer* timer) {
  return readCount(q, run(q, Mode::Indices, flags, flags, out, n, timer));
}

std::size_t Compactor::unique(cl::CommandQueue& q, const cl::Buffer& sorted_keys, cl::Buffer& out, std::size_t n,
                              ClPassTimer* timer) {
  return readCount(q, run(q, Mode::Unique, sorted_keys, sorted_keys, out, n, timer));
}

void Compactor::compactAsync(cl::CommandQueue& q, const cl::Buffer& in, const cl::Buffer& flags, cl::Buffer& out,
                             std::size_t n, cl::Buffer& count, std::size_t count_index, ClPassTimer* timer) {
  copyCount(q, run(q, Mode::Values, in, flags, out, n, timer), count, count_index);
}

void Compactor::compactIndicesAsync(cl::CommandQueue& q, const cl::Buffer& flags, cl::Buffer& out, std::size_t n,
                                    cl::Buffer& count, std::size_t count_index, ClPassTimer* timer) {
  copyCount(q, run(q, Mode::Indices, flags, flags, out, n, timer), count, count_index);
}

void Compactor::uniqueAsync(cl::CommandQueue& q, const cl::Buffer& sorted_keys, cl::Buffer& out, std::size_t n,
                            cl::Buffer& count, std::size_t count_index, ClPassTimer* timer) {
  copyCount(q, run(q, Mode::Unique, sorted_keys, sorted_keys, out, n, timer), count, count_index);
}

std::size_t compact(cl::CommandQueue& q, const cl::Buffer& in, const cl::Buffer& flags, cl::Buffer& out,
                    std::size_t n) {
  auto s = detail::sharedFor<Compactor>(q);
  return s.obj.compact(q, in, flags, out, n);
}

std::size_t unique(cl::CommandQueue& q, const cl::Buffer& sorted_keys, cl::Buffer& out, std::size_t n) {
  auto s = detail::sharedFor<Compactor>(q);
  return s.obj.unique(q, sorted_keys, out, n);
}

}  // namespace ml::compute
