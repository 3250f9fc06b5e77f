#include "host/reference/ReferenceCache.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace ml {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'M', 'L', 'G', 'I', 'R', 'E', 'F', '1'};

// FNV-1a, 64 bits: enough to tell apart the references of one user's sweeps.
struct Fnv {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    value(v.size());
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
};

void hashScene(Fnv& f, const Scene& scene) {
  f.vec(scene.vertices);  // Vertex: 32 bytes of floats, no padding (Scene.hpp)
  f.vec(scene.indices);
  static_assert(sizeof(DrawBatch) == 12, "three uint32, no padding bytes to hash");
  for (const DrawBatch& b : scene.batches) f.value(b);
  for (const Material& m : scene.materials) f.value(m.base_color), f.value(m.base_color_texture);
  for (const Texture& t : scene.textures) f.value(t.width), f.value(t.height), f.vec(t.rgba8);
}

fs::path cacheFolder() {
  if (const char* off = std::getenv("MANYLIGHTS_GI_REFERENCE_CACHE"); off && std::string(off) == "0") return {};
  if (const char* d = std::getenv("MANYLIGHTS_CACHE_DIR"); d && *d) return fs::path(d) / "gi-reference";
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "manylights/gi-reference";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache/manylights/gi-reference";
  return {};
}

bool readFile(const fs::path& file, std::uint64_t key, unsigned w, unsigned h, IndirectImage& out) {
  std::ifstream in(file, std::ios::binary);
  char magic[8];
  std::uint64_t k = 0;
  std::uint32_t fw = 0, fh = 0;
  if (!in.read(magic, 8) || std::memcmp(magic, kMagic, 8) != 0) return false;
  if (!in.read(reinterpret_cast<char*>(&k), 8) || !in.read(reinterpret_cast<char*>(&fw), 4) ||
      !in.read(reinterpret_cast<char*>(&fh), 4) || k != key || fw != w || fh != h)
    return false;
  out.width = w, out.height = h;
  out.rgba.resize(std::size_t(w) * h * 4);
  if (!in.read(reinterpret_cast<char*>(out.rgba.data()), std::streamsize(out.rgba.size() * 4))) return false;
  if (in.peek() == std::char_traits<char>::eof()) return true;  // a one-sample reference: no noise estimate
  out.noise_var.resize(std::size_t(w) * h);
  return in.read(reinterpret_cast<char*>(out.noise_var.data()), std::streamsize(out.noise_var.size() * 4)) &&
         in.peek() == std::char_traits<char>::eof();
}

void writeFile(const fs::path& file, std::uint64_t key, const IndirectImage& img) {
  std::error_code ec;
  fs::create_directories(file.parent_path(), ec);
  const fs::path tmp = file.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    const std::uint32_t w = img.width, h = img.height;
    out.write(kMagic, 8);
    out.write(reinterpret_cast<const char*>(&key), 8);
    out.write(reinterpret_cast<const char*>(&w), 4);
    out.write(reinterpret_cast<const char*>(&h), 4);
    out.write(reinterpret_cast<const char*>(img.rgba.data()), std::streamsize(img.rgba.size() * 4));
    out.write(reinterpret_cast<const char*>(img.noise_var.data()), std::streamsize(img.noise_var.size() * 4));
    if (!out) {
      spdlog::warn("gi reference cache: cannot write {}; references are traced every time", tmp.string());
      fs::remove(tmp, ec);
      return;
    }
  }
  fs::rename(tmp, file, ec);
  if (ec) spdlog::warn("gi reference cache: cannot write {}: {}", file.string(), ec.message());
}

}  // namespace

std::uint64_t indirectReferenceKey(const Scene& scene, const std::vector<gpu::PointLight>& lights,
                                   const Camera& camera, unsigned width, unsigned height,
                                   const IndirectOptions& options) {
  Fnv f;
  f.value(kIndirectTracerVersion);
  hashScene(f, scene);
  f.vec(lights);
  f.value(camera.eye), f.value(camera.center), f.value(camera.up);
  f.value(camera.fovy_degrees), f.value(camera.near_plane), f.value(camera.far_plane);
  f.value(width), f.value(height), f.value(options.samples), f.value(options.seed);
  f.value(static_cast<unsigned char>(options.shadow_rays));
  f.value(options.bounces);
  return f.h;
}

CachedReference cachedIndirectReference(const Scene& scene, const std::vector<gpu::PointLight>& lights,
                                        const Camera& camera, unsigned width, unsigned height,
                                        const IndirectOptions& options) {
  CachedReference r;
  const fs::path folder = cacheFolder();
  const std::uint64_t key = indirectReferenceKey(scene, lights, camera, width, height, options);
  if (!folder.empty()) {
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.ref", static_cast<unsigned long long>(key));
    r.file = (folder / name).string();
    const auto start = std::chrono::steady_clock::now();
    if (readFile(r.file, key, width, height, r.image)) {
      r.from_cache = true;
      r.image.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      return r;
    }
  }
  r.image = traceIndirectReference(scene, lights, camera, width, height, options);
  if (!r.file.empty()) writeFile(r.file, key, r.image);
  return r;
}

}  // namespace ml
