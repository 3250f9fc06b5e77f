#include "host/cl/ProgramBuilder.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "host/cl/ClRuntime.hpp"
#include "host/util/EmbeddedFiles.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace fs = std::filesystem;

std::uint64_t fnv1a64(std::string_view data, std::uint64_t seed) {
  std::uint64_t h = seed;
  for (unsigned char c : data) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

namespace {

std::string defaultCacheDir() {
  if (const char* dir = std::getenv("MANYLIGHTS_CACHE_DIR"); dir && *dir) {
    if (std::string_view(dir) == "off") return {};
    return std::string(dir) + "/kernels";
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/manylights/kernels";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/manylights/kernels";
  return {};
}

std::string hex(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

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
    : context_(std::move(context)), device_(std::move(device)), cache_dir_(defaultCacheDir()) {
  device_id_ = info.platform_name + "|" + info.platform_version + "|" + info.name + "|" + info.version + "|" +
               info.driver_version;
}

cl::Program ProgramBuilder::build(std::string_view file, const Defines& defines) {
  std::string key = "kernels/" + std::string(file);
  if (!hasEmbeddedFile(key)) throw UserError("kernel file 'kernels/" + std::string(file) + "' does not exist");
  return buildSource(key, readEmbeddedFile(key), defines);
}

cl::Program ProgramBuilder::buildSource(std::string_view name, const std::string& source, const Defines& defines) {
  std::string expanded = expandIncludes(name, source);
  std::string options = baseBuildOptions(device_);
  for (const auto& [k, v] : defines) options += " -D " + k + "=" + v;
  std::uint64_t key = fnv1a64(expanded);
  key = fnv1a64(options, key);
  key = fnv1a64(device_id_, key);

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
  const std::string path = cache_dir_.empty() ? std::string() : cache_dir_ + "/" + hex(key) + ".bin";
  // 1. Cached binary.
  if (!path.empty()) {
    std::ifstream in(path, std::ios::binary);
    if (in) {
      std::vector<unsigned char> bin((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      try {
        cl::Program::Binaries bins{bin};
        std::vector<cl_int> status;
        cl::Program p(context_, {device_}, bins, &status);
        p.build({device_}, options.c_str());
        ++stats_.disk_hits;
        return p;
      } catch (const cl::Error&) {
        // Stale or corrupt entry (e.g. driver update): fall through and rebuild.
      }
    }
  }
  // 2. Compile from source.
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
  // 3. Store the binary (atomically: write then rename, so parallel runs never read half a file).
  if (!path.empty()) {
    try {
      auto bins = program.getInfo<CL_PROGRAM_BINARIES>();
      if (!bins.empty() && !bins.front().empty()) {
        std::error_code ec;
        fs::create_directories(cache_dir_, ec);
        const std::string tmp = path + ".tmp" + std::to_string(std::rand());
        {
          std::ofstream out(tmp, std::ios::binary);
          out.write(reinterpret_cast<const char*>(bins.front().data()), static_cast<std::streamsize>(bins.front().size()));
        }
        fs::rename(tmp, path, ec);
        if (ec) fs::remove(tmp, ec);
      }
    } catch (const cl::Error&) {
      // A device that cannot return binaries simply is not cached.
    }
  }
  return program;
}

}  // namespace ml
