#include "host/cl/KernelCacheProbe.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string_view>
#include <thread>
#include <vector>

namespace ml {

namespace {

constexpr int kRefusedSafely = 0;
constexpr int kAccepted = 3;
constexpr int kNoContext = 4;

// Runs in the forked child: only raw OpenCL calls and _exit (no destructors,
// no atexit handlers of the parent's objects).
[[noreturn]] void childProbe(cl_device_id device) {
  const int null_fd = ::open("/dev/null", O_WRONLY);
  if (null_fd >= 0) {
    ::dup2(null_fd, STDOUT_FILENO);  // a panicking driver prints its backtrace
    ::dup2(null_fd, STDERR_FILENO);
  }
  cl_int err = CL_SUCCESS;
  cl_context ctx = clCreateContext(nullptr, 1, &device, nullptr, nullptr, &err);
  if (err != CL_SUCCESS || !ctx) ::_exit(kNoContext);
  const std::vector<unsigned char> zeros(4096, 0);
  const unsigned char* bytes = zeros.data();
  const std::size_t size = zeros.size();
  cl_int status = CL_SUCCESS;
  cl_program p = clCreateProgramWithBinary(ctx, 1, &device, &size, &bytes, &status, &err);
  if (err != CL_SUCCESS || !p) ::_exit(kRefusedSafely);
  err = clBuildProgram(p, 1, &device, "", nullptr, nullptr);
  ::_exit(err != CL_SUCCESS ? kRefusedSafely : kAccepted);
}

// The child's wait status, or nothing after `limit` (the child is then killed).
bool waitChild(pid_t pid, std::chrono::seconds limit, int& status) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  for (;;) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) return true;
    if (r < 0) return false;
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

bool probe(const cl::Device& device) {
  std::fflush(nullptr);  // the child must not flush the parent's buffered output again
  const pid_t pid = ::fork();
  if (pid < 0) return false;
  if (pid == 0) childProbe(device());
  int status = 0;
  if (!waitChild(pid, std::chrono::seconds(30), status)) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == kRefusedSafely;
}

}  // namespace

bool driverRefusesBinariesSafely(const cl::Device& device, const std::string& driver_key) {
  if (const char* hook = std::getenv("MANYLIGHTS_TEST_BINARIES"); hook && std::string_view(hook) == "unsafe")
    return false;
  static std::mutex mutex;
  static std::map<std::string, bool> known;
  const std::lock_guard<std::mutex> lock(mutex);
  if (const auto it = known.find(driver_key); it != known.end()) return it->second;
  const bool safe = probe(device);
  known.emplace(driver_key, safe);
  return safe;
}

}  // namespace ml
