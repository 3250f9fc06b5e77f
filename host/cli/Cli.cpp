#include "host/cli/Cli.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <new>

#include "gl/GlPassTimer.hpp"
#include "host/app/BenchCommand.hpp"
#include "host/app/CompareReferenceCommand.hpp"
#include "host/app/DevicesCommand.hpp"
#include "gl/GlContext.hpp"
#include "host/app/RenderCommand.hpp"
#include "host/app/ViewCommand.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/cl/KernelCache.hpp"
#include "host/util/EmbeddedFiles.hpp"
#include "host/util/Error.hpp"

namespace ml {

namespace {
// OpenCL codes of a buffer or image that did not fit: the run asked for too
// much (a flag's fault), not an internal error.
bool isAllocationFailure(cl_int code) {
  return code == CL_MEM_OBJECT_ALLOCATION_FAILURE || code == CL_OUT_OF_RESOURCES || code == CL_OUT_OF_HOST_MEMORY ||
         code == CL_INVALID_BUFFER_SIZE;
}

// The subcommands and the structs their flags fill.
struct CommandLine {
  CLI::App app{"manylights: light assignment for many dynamic point lights (OpenCL + OpenGL)"};
  RenderArgs render_args;
  BenchArgs bench_args;
  CompareReferenceArgs compare_args;
  ViewArgs view_args;
  CLI::App* devices = app.add_subcommand("devices", "List OpenCL platforms and their devices with indices");
  CLI::App* techniques_cmd = app.add_subcommand("techniques", "List the registered light-assignment techniques");
  CLI::App* render = addRenderCommand(app, render_args);
  CLI::App* bench = addBenchCommand(app, bench_args);
  CLI::App* compare = addCompareReferenceCommand(app, compare_args);
  CLI::App* view = addViewCommand(app, view_args);

  CommandLine() { app.require_subcommand(1); }
  // -1 when a subcommand is to run; else the exit code (help: 0, parse error: 2).
  int parse(int argc, char** argv) {
    try {
      app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
      return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
      return app.exit(e);
    } catch (const CLI::ParseError& e) {
      std::fprintf(stderr, "manylights: error: %s\n", e.what());
      return 2;
    }
    return -1;
  }
};
}  // namespace

int parseCli(int argc, char** argv) { return CommandLine().parse(argc, argv); }

int runCli(int argc, char** argv) {
  CommandLine cli;
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  auto* devices = cli.devices;
  auto* techniques_cmd = cli.techniques_cmd;
  auto* render = cli.render;
  auto* bench = cli.bench;
  auto* compare = cli.compare;
  auto& render_args = cli.render_args;
  auto& bench_args = cli.bench_args;
  auto& compare_args = cli.compare_args;
  try {
    if (devices->parsed()) return runDevices();
    if (techniques_cmd->parsed()) {
      for (const auto& t : techniques()) std::printf("%-20s %s\n", t.name.c_str(), t.description.c_str());
      return 0;
    }
    // Environment first, so a bad value is the run's only line and a cache
    // warning comes before the start-up lines.
    glTimingModeFromEnv();
    sourceDirFromEnv();
    KernelCache::checkEnvironment();
    if (render->parsed()) return runRender(render_args);
    if (bench->parsed()) {
      // The program by its name only: results files carry no machine paths.
      bench_args.command_line = argc > 0 ? std::filesystem::path(argv[0]).filename().string() : "manylights";
      for (int i = 1; i < argc; ++i) bench_args.command_line += " " + std::string(argv[i]);
      return runBench(bench_args);
    }
    if (compare->parsed()) return runCompareReference(compare_args);
    if (cli.view->parsed()) return runView(cli.view_args);
  } catch (const UserError& e) {
    std::fprintf(stderr, "manylights: error: %s\n", e.what());
    return 2;
  } catch (const cl::Error& e) {
    std::fprintf(stderr, "manylights: error: OpenCL: %s%s\n", describeClError(e).c_str(),
                 isAllocationFailure(e.err()) ? " (the device is out of memory: lower --lights or --size)" : "");
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "manylights: error: out of host memory (lower --lights or --size; docs/usage.md, \"Bad input\")\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "manylights: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}

}  // namespace ml
