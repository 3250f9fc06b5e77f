#include "host/compute/FittedProgram.hpp"

#include <algorithm>
#include <iostream>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "host/compute/Detail.hpp"
#include "host/util/Error.hpp"

namespace ml::compute {

using detail::prevPow2;

namespace {

// The largest power of two <= wg that every kernel of `p` accepts, judged by
// what the driver reports for the build at hand (0 when even 1 does not fit).
std::size_t acceptedWg(const ComputeEnv& env, cl::Program p, const std::size_t built) {
  std::size_t wg = built;
  std::vector<cl::Kernel> kernels;
  p.createKernels(&kernels);
  const cl_ulong device_local = env.device().getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
  for (const cl::Kernel& k : kernels) {
    const std::size_t max_wg = k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(env.device());
    if (max_wg < wg) wg = max_wg ? prevPow2(max_wg) : 0;
    // The __local arrays are sized by WG: half the items, about half the bytes.
    if (k.getWorkGroupInfo<CL_KERNEL_LOCAL_MEM_SIZE>(env.device()) > device_local) wg = std::min(wg, built / 2);
  }
  return wg;
}

void noteLowered(const char* what, std::size_t requested, std::size_t wg, const std::string& device) {
  static std::mutex mutex;
  static auto* noted = new std::set<std::string>();
  const std::string key = std::string(what) + " " + std::to_string(requested) + " " + std::to_string(wg) + device;
  std::lock_guard lock(mutex);
  if (!noted->insert(key).second) return;
  std::cerr << "note: " << what << ": work_group_size " << requested << " lowered to " << wg
            << ", the most its kernels run with on '" << device << "'\n";
}

}  // namespace

FittedProgram buildFitted(const ComputeEnv& env, const Tuning& t, const char* file, const char* what,
                          const std::function<Defines(std::size_t wg)>& extra) {
  if (!t.gpu()) return {buildShaped(env, t, file, extra ? extra(1) : Defines{}), 1};
  Tuning fitted = t;
  for (;;) {
    cl::Program p = buildShaped(env, fitted, file, extra ? extra(fitted.wg) : Defines{});
    const std::size_t accepted = acceptedWg(env, p, fitted.wg);
    if (accepted == fitted.wg) {
      if (t.requested_wg > fitted.wg) noteLowered(what, t.requested_wg, fitted.wg, env.info().name);
      return {p, fitted.wg};
    }
    if (accepted == 0)
      throw UserError(std::string(what) + ": the device '" + env.info().name +
                      "' runs its work-group kernels with no group size at all; use the CPU shape");
    fitted.wg = accepted;
  }
}

cl::Program buildShaped(const ComputeEnv& env, const Tuning& t, const char* file, Defines extra) {
  Defines d;
  d.emplace_back("ML_GPU", t.gpu() ? "1" : "0");
  if (t.gpu()) {
    d.emplace_back("WG", std::to_string(t.wg));
    d.emplace_back("ITEMS", std::to_string(t.items));
  }
  for (auto& e : extra) d.push_back(std::move(e));
  return env.programs().build(file, d);
}

}  // namespace ml::compute
