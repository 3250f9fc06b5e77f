#pragma once
// Output files of the commands (--out, --heatmap, --json, --csv, --plot,
// --images, ...), checked before any work starts and written so that a run
// that fails or is interrupted never leaves a complete-looking file:
//   - requireOutputFile / requireOutputDir create missing parent folders and
//     prove the folder takes a new file (a probe file is created and removed),
//     so an unwritable path is one line naming its flag, before the first frame;
//     paths under /proc or /sys (as written or through links) are refused
//     first, whoever runs the command (root can create things there);
//   - writeFileAtomically / writeImageAtomically write a temporary file next to
//     the target and rename it over the target only once it is complete; a
//     link to a file is written through (the link stays). Targets that are
//     not files (devices, pipes, sockets) and the process's own stdout/stderr
//     under any name (/dev/stdout, also redirected to a file) are written in
//     place instead, after what the process printed before (no rename there:
//     it would replace /dev/stdout itself).
// Every failure is a UserError naming the flag and the path. Reports name
// input files through reportPath.
#include <string>
#include <vector>

namespace ml {

// `path` is a file that will be written: not a folder, its folder exists (made
// if missing) and takes new files. No-op for an empty path.
void requireOutputFile(const std::string& flag, const std::string& path);
// `dir` is a folder that files will be written into (made if missing).
void requireOutputDir(const std::string& flag, const std::string& dir);
// Image outputs are written as PNG (8-bit) or OpenEXR (float), chosen by the
// extension; any other extension is refused (one line listing the accepted).
void requireImageFile(const std::string& flag, const std::string& path);

void writeFileAtomically(const std::string& flag, const std::string& path, const std::string& bytes);
// writeImage (host/util/ImageIO.hpp) through a temporary file with the same extension.
void writeImageAtomically(const std::string& flag, const std::string& path, unsigned width, unsigned height,
                          unsigned channels, const std::vector<float>& pixels_bottom_up);

// `path` as printed output and results files record it, without machine
// paths: "data/..." for the project's data folder (wherever it is), relative
// to the working folder when it lies below it, else as given.
std::string reportPath(const std::string& path);

}  // namespace ml
