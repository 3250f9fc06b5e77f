#include "host/vct/HashedListsCl.hpp"

#include <stdexcept>
#include <string>

#include "host/cl/Launch.hpp"
#include "host/compute/FittedProgram.hpp"
#include "host/compute/HostIo.hpp"
#include "host/util/Error.hpp"

namespace ml::vct {

HashedListsCl::HashedListsCl(const compute::ComputeEnv& env) : env_(env) {}

void HashedListsCl::grow(Grown& g, std::size_t words) {
  const std::size_t bytes = words * 4;
  if (bytes > env_.info().max_alloc_size)
    throw UserError("hashed light lists need " + std::to_string(bytes) +
                    " bytes in one buffer, more than the device's max allocation");
  g.buf = cl::Buffer(env_.context(), CL_MEM_READ_ONLY, bytes);
  g.capacity = bytes;
}

// Non-blocking writes from the plan's sources (the octree and the plan's
// image), which live until the queue has finished with them below.
void HashedListsCl::upload(cl::CommandQueue& q, hashed::LinklessOctree& octree, bool rebuilt) {
  Grown* buffers[hashed::kGpuArrayCount] = {&header_, &offsets_, &desc_, &data_, &list_};  // GpuArray order
  hashed::GpuArrayWords capacity{};
  for (unsigned i = 0; i < hashed::kGpuArrayCount; ++i) capacity[i] = buffers[i]->capacity / 4;
  const hashed::GpuUploadPlan plan = planner_.plan(octree, rebuilt || !uploaded_, capacity);
  for (unsigned i = 0; i < hashed::kGpuArrayCount; ++i)
    if (plan.grow[i]) grow(*buffers[i], plan.grow[i]);
  for (const hashed::GpuWrite& w : plan.writes)
    q.enqueueWriteBuffer(buffers[unsigned(w.array)]->buf, CL_FALSE, w.word * 4, w.count * 4, w.src);
  q.finish();
  uploaded_ = true;
  upload_full_ = plan.full;
  upload_bytes_ = plan.bytes();
}

std::string HashedListsCl::staleArray(cl::CommandQueue& q, const hashed::LinklessOctree& octree) const {
  const Grown* buffers[hashed::kGpuArrayCount] = {&header_, &offsets_, &desc_, &data_, &list_};
  return hashed::firstStaleArray(octree, [&](hashed::GpuArray a, std::size_t words) {
    const Grown& g = *buffers[unsigned(a)];
    if (words * 4 > g.capacity) return std::vector<std::uint32_t>{};  // cannot hold the image: stale
    return compute::download<std::uint32_t>(q, g.buf, words);
  });
}

void HashedListsCl::setArgs(cl::Kernel& k, cl_uint first) const {
  if (!uploaded_) throw std::logic_error("HashedListsCl::setArgs before upload()");
  k.setArg(first, header_.buf);
  k.setArg(first + 1, offsets_.buf);
  k.setArg(first + 2, desc_.buf);
  k.setArg(first + 3, data_.buf);
  k.setArg(first + 4, list_.buf);
}

std::vector<hashed::LinklessOctree::Range> HashedListsCl::lookup(cl::CommandQueue& q,
                                                                 const std::vector<gpu::ml_float4>& points) {
  if (!probe_()) probe_ = cl::Kernel(env_.programs().build("vct/vct_inject.cl", {{"ML_GPU", "0"}}), "hashed_lookup_probe");
  cl::Buffer in = compute::upload(env_.context(), q, points);
  cl::Buffer out(env_.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(points.size() * 16, 16));
  compute::poison(q, out);
  ml::setArgs(probe_, in, u32(points.size()), out);
  setArgs(probe_, 3);
  launchTimed(q, probe_, points.size(), 1, nullptr, "");
  const auto words = compute::download<std::uint32_t>(q, out, points.size() * 4);
  std::vector<hashed::LinklessOctree::Range> r(points.size());
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = {words[4 * i], words[4 * i + 1], words[4 * i + 2]};
  return r;
}

std::size_t HashedListsCl::bytes() const {
  return header_.capacity + offsets_.capacity + desc_.capacity + data_.capacity + list_.capacity;
}

}  // namespace ml::vct
