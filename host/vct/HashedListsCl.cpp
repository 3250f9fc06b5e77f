#include "host/vct/HashedListsCl.hpp"

#include <stdexcept>
#include <string>

#include "host/compute/Detail.hpp"
#include "host/compute/HostIo.hpp"
#include "host/util/Error.hpp"

namespace ml::vct {

HashedListsCl::HashedListsCl(const compute::ComputeEnv& env) : env_(env) {}

void HashedListsCl::put(cl::CommandQueue& q, Grown& g, const std::vector<std::uint32_t>& words) {
  const std::size_t bytes = std::max<std::size_t>(words.size() * 4, 16);
  if (bytes > g.capacity) {
    if (bytes > env_.info().max_alloc_size)
      throw UserError("hashed light lists need " + std::to_string(bytes) +
                      " bytes in one buffer, more than the device's max allocation");
    g.buf = cl::Buffer(env_.context(), CL_MEM_READ_ONLY, bytes);
    g.capacity = bytes;
  }
  if (!words.empty()) q.enqueueWriteBuffer(g.buf, CL_TRUE, 0, words.size() * 4, words.data());
}

void HashedListsCl::upload(cl::CommandQueue& q, const hashed::LinklessOctree& octree) {
  const auto im = octree.packGpuImage();
  put(q, header_, im.header);
  put(q, offsets_, im.offsets);
  put(q, desc_, im.desc);
  put(q, data_, im.data);
  put(q, list_, octree.pool().list());
  uploaded_ = true;
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
  if (!probe_()) probe_ = cl::Kernel(env_.programs().build("vct_inject.cl", {{"ML_GPU", "0"}}), "hashed_lookup_probe");
  cl::Buffer in = compute::upload(env_.context(), q, points);
  cl::Buffer out(env_.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(points.size() * 16, 16));
  compute::poison(q, out);
  ml::setArgs(probe_, in, compute::detail::u32(points.size()), out);
  setArgs(probe_, 3);
  compute::detail::launch(q, probe_, points.size(), 1, nullptr, "");
  const auto words = compute::download<std::uint32_t>(q, out, points.size() * 4);
  std::vector<hashed::LinklessOctree::Range> r(points.size());
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = {words[4 * i], words[4 * i + 1], words[4 * i + 2]};
  return r;
}

std::size_t HashedListsCl::bytes() const {
  return header_.capacity + offsets_.capacity + desc_.capacity + data_.capacity + list_.capacity;
}

}  // namespace ml::vct
