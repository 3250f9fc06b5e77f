#include "host/cl/ProgramBuilder.hpp"

#include <cstdio>
#include <set>
#include <sstream>

#include "host/cl/ClRuntime.hpp"
#include "host/cl/KernelCacheProbe.hpp"
#include "host/util/EmbeddedFiles.hpp"
#include "host/util/Error.hpp"

namespace ml {

std::uint64_t fnv1a64(std::string_view data, std::uint64_t seed) {
  std::uint64_t h = seed;
  for (unsigned char c : data) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

namespace {

void expandInto(std::string_view name, const std::string& source, std::set<std::string>& seen, std::string& out) {
  std::istringstream in(source);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    auto first = line.find_first_not_of(" \t");
    // Only quoted includes are ours; <system> includes sit in the host-only
    // branches of shared headers and are left for the preprocessor to skip.
    if (first != std::string::npos && line.compare(first, 8, "#include") == 0 &&
        line.find('<', first) == std::string::npos) {
      auto q1 = line.find('"', first);
      auto q2 = q1 == std::string::npos ? q1 : line.find('"', q1 + 1);
      if (q1 == std::string::npos || q2 == std::string::npos)
        throw UserError(std::string(name) + ":" + std::to_string(line_no) + ": only #include \"file\" is supported");
      std::string inc = line.substr(q1 + 1, q2 - q1 - 1);
      std::string key = inc.ends_with(".cl") ? "kernels/" + inc : "shared/" + inc;
      if (!hasEmbeddedFile(key))
        throw UserError(std::string(name) + ":" + std::to_string(line_no) + ": included file '" + inc +
                        "' is neither in kernels/ nor host/shared/");
      if (seen.insert(key).second) {
        out += "#line 1 \"" + inc + "\"\n";
        expandInto(key, readEmbeddedFile(key), seen, out);
        out += "#line " + std::to_string(line_no + 1) + " \"" + std::string(name) + "\"\n";
      } else {
        out += "\n";
      }
      continue;
    }
    out += line;
    out += '\n';
  }
}

}  // namespace

std::string ProgramBuilder::expandIncludes(std::string_view name, const std::string& source) {
  std::set<std::string> seen;
  std::string out;
  expandInto(name, source, seen, out);
  return out;
}

ProgramBuilder::ProgramBuilder(cl::Context context, cl::Device device, const DeviceInfo& info)
    : ProgramBuilder(std::move(context), std::move(device), info, KernelCache::fromEnvironment()) {}

ProgramBuilder::ProgramBuilder(cl::Context context, cl::Device device, const DeviceInfo& info, KernelCache cache)
    : context_(std::move(context)), device_(std::move(device)), cache_(std::move(cache)) {
  device_id_ = info.platform_name + "|" + info.platform_version + "|" + info.name + "|" + info.version + "|" +
               info.driver_version;
}

cl::Program ProgramBuilder::build(std::string_view file, const Defines& defines) {
  std::string key = "kernels/" + std::string(file);
  if (!hasEmbeddedFile(key)) throw UserError("kernel file 'kernels/" + std::string(file) + "' does not exist");
  return buildSource(key, readEmbeddedFile(key), defines);
}

std::string ProgramBuilder::options(const Defines& defines) const {
  std::string options = baseBuildOptions(device_);
  for (const auto& [k, v] : defines) options += " -D " + k + "=" + v;
  return options;
}

std::uint64_t ProgramBuilder::cacheKey(std::string_view name, const std::string& source, const Defines& defines) const {
  std::uint64_t key = fnv1a64(expandIncludes(name, source));
  key = fnv1a64(options(defines), key);
  return fnv1a64(device_id_, key);
}

bool ProgramBuilder::cachesBinaries() {
  if (!cache_.enabled()) return false;
  if (!driver_refuses_safely_) driver_refuses_safely_ = driverRefusesBinariesSafely(device_, device_id_);
  return *driver_refuses_safely_;
}

cl::Program ProgramBuilder::buildSource(std::string_view name, const std::string& source, const Defines& defines) {
  const std::string expanded = expandIncludes(name, source);
  const std::string options = this->options(defines);
  const std::uint64_t key = cacheKey(name, source, defines);

  std::lock_guard lock(mutex_);
  if (auto it = memo_.find(key); it != memo_.end()) {
    ++stats_.memory_hits;
    return it->second;
  }
  cl::Program program = compile(name, expanded, options, key);
  memo_.emplace(key, program);
  return program;
}

cl::Program ProgramBuilder::compile(std::string_view name, const std::string& source, const std::string& options,
                                    std::uint64_t key) {
  const bool binaries = cachesBinaries();
  if (auto cached = binaries ? fromCache(options, key) : std::nullopt) {
    ++stats_.disk_hits;
    return *cached;
  }
  cl::Program program;
  try {
    program = cl::Program(context_, source);
    program.build({device_}, options.c_str());
  } catch (const cl::Error& e) {
    std::string log;
    try {
      log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_);
    } catch (const cl::Error&) {
    }
    throw UserError("kernel build failed: " + std::string(name) + " (" + options + "): " + clErrorName(e.err()) +
                    "\n--- build log ---\n" + log);
  }
  ++stats_.compiles;
  if (binaries) storeInCache(program, key);
  return program;
}

std::optional<cl::Program> ProgramBuilder::fromCache(const std::string& options, std::uint64_t key) {
  // load() has checked size, key and checksum: the driver never sees a damaged file.
  auto binary = cache_.load(key);
  if (!binary) return std::nullopt;
  try {
    std::vector<cl_int> status;
    cl::Program p(context_, {device_}, cl::Program::Binaries{*binary}, &status);
    p.build({device_}, options.c_str());
    return p;
  } catch (const cl::Error& e) {
    // An intact file the driver still refuses (e.g. written by another driver
    // build with the same version strings): drop it rather than fail every run.
    cache_.discard(key, "was refused by the OpenCL driver (" + clErrorName(e.err()) + ")");
    return std::nullopt;
  }
}

void ProgramBuilder::storeInCache(const cl::Program& program, std::uint64_t key) {
  if (!cache_.enabled()) return;
  std::vector<std::vector<unsigned char>> bins;
  try {
    bins = program.getInfo<CL_PROGRAM_BINARIES>();
  } catch (const cl::Error&) {
    return;  // a device that cannot return binaries simply is not cached
  }
  if (!bins.empty()) cache_.store(key, bins.front());
}

}  // namespace ml
