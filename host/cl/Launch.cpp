#include "host/cl/Launch.hpp"

#include <stdexcept>
#include <string>

namespace ml {

void requireCount(std::size_t n, const char* what) {
  if (n > 0xFFFFFFFFull) throw std::invalid_argument(std::string(what) + ": n must fit in 32 bits");
}

void requireBuffer(const cl::Buffer& buf, std::size_t bytes, const char* what) {
  if (bytes == 0) return;
  if (!buf()) throw std::invalid_argument(std::string(what) + ": null buffer");
  const std::size_t size = buf.getInfo<CL_MEM_SIZE>();
  if (size < bytes)
    throw std::invalid_argument(std::string(what) + ": buffer holds " + std::to_string(size) + " bytes, " +
                                std::to_string(bytes) + " needed");
}

bool sameBuffer(const cl::Buffer& a, const cl::Buffer& b) { return a() == b(); }

void launchTimed(cl::CommandQueue& q, const cl::Kernel& k, std::size_t global, std::size_t local, ClPassTimer* timer,
                 const char* name) {
  if (global == 0) return;
  q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(roundUp(global, local)), cl::NDRange(local), nullptr,
                         timer ? timer->next(name) : nullptr);
}

}  // namespace ml
