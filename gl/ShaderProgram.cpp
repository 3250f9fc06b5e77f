#include "gl/ShaderProgram.hpp"

#include <set>
#include <sstream>

#include "gl/GlCheck.hpp"
#include "host/util/EmbeddedFiles.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

// Shader files, then the headers shared with C++ and OpenCL (host/shared/,
// e.g. depth_convention.h, written to compile as GLSL too).
std::string embeddedName(const std::string& file) {
  const bool shared = !hasEmbeddedFile("shaders/" + file) && hasEmbeddedFile("shared/" + file);
  return (shared ? "shared/" : "shaders/") + file;
}

void expandInto(const std::string& file, const ShaderAliases& aliases, std::set<std::string>& seen,
                std::string& out) {
  std::istringstream in(readEmbeddedFile(embeddedName(file)));
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    auto first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line.compare(first, 8, "#include") == 0) {
      auto q1 = line.find('"', first);
      auto q2 = q1 == std::string::npos ? q1 : line.find('"', q1 + 1);
      if (q2 == std::string::npos)
        throw UserError("gl/shaders/" + file + ":" + std::to_string(line_no) + ": malformed #include");
      std::string inc = line.substr(q1 + 1, q2 - q1 - 1);
      for (const auto& [from, to] : aliases)
        if (inc == from) inc = to;
      if (!hasEmbeddedFile(embeddedName(inc)))
        throw UserError("gl/shaders/" + file + ":" + std::to_string(line_no) + ": no shader file '" + inc + "'");
      if (seen.insert(inc).second) expandInto(inc, aliases, seen, out);
      continue;
    }
    out += line;
    out += '\n';
  }
}

GLenum stageOf(const std::string& file) {
  auto ext = file.substr(file.find_last_of('.') + 1);
  if (ext == "vert") return GL_VERTEX_SHADER;
  if (ext == "frag") return GL_FRAGMENT_SHADER;
  if (ext == "comp") return GL_COMPUTE_SHADER;
  if (ext == "geom") return GL_GEOMETRY_SHADER;
  throw UserError("gl/shaders/" + file + ": unknown shader stage extension '" + ext + "'");
}

}  // namespace

std::string expandShaderSource(const std::string& file, const ShaderDefines& defines,
                               const ShaderAliases& aliases) {
  std::string out = "#version 450 core\n";
  for (const auto& [k, v] : defines) out += "#define " + k + " " + v + "\n";
  std::set<std::string> seen;
  expandInto(file, aliases, seen, out);
  return out;
}

ShaderProgram::ShaderProgram(const std::vector<std::string>& files, const ShaderDefines& defines,
                             const ShaderAliases& aliases) {
  for (const auto& f : files) label_ += (label_.empty() ? "" : "+") + f;
  std::vector<GLuint> shaders;
  auto cleanup = [&] {
    for (GLuint s : shaders) glDeleteShader(s);
  };
  for (const auto& f : files) {
    const std::string src = expandShaderSource(f, defines, aliases);
    GLuint s = glCreateShader(stageOf(f));
    const char* p = src.c_str();
    glShaderSource(s, 1, &p, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    shaders.push_back(s);
    if (!ok) {
      GLint len = 0;
      glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
      std::string log(static_cast<size_t>(len > 0 ? len : 1), '\0');
      glGetShaderInfoLog(s, len, nullptr, log.data());
      cleanup();
      throw UserError("shader compile failed: gl/shaders/" + f + "\n" + log);
    }
  }
  id_ = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(id_, s);
  glLinkProgram(id_);
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  cleanup();
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<size_t>(len > 0 ? len : 1), '\0');
    glGetProgramInfoLog(id_, len, nullptr, log.data());
    glDeleteProgram(id_);
    id_ = 0;
    throw UserError("shader link failed: " + label_ + "\n" + log);
  }
  glCheck(("building shader program " + label_).c_str());
}

ShaderProgram::~ShaderProgram() {
  if (id_) glDeleteProgram(id_);
}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& o) noexcept {
  if (this != &o) {
    if (id_) glDeleteProgram(id_);
    id_ = std::exchange(o.id_, 0);
    label_ = std::move(o.label_);
  }
  return *this;
}

void ShaderProgram::use() const { glUseProgram(id_); }
void ShaderProgram::set(const char* n, int v) const { glProgramUniform1i(id_, loc(n), v); }
void ShaderProgram::set(const char* n, unsigned v) const { glProgramUniform1ui(id_, loc(n), v); }
void ShaderProgram::set(const char* n, float v) const { glProgramUniform1f(id_, loc(n), v); }
void ShaderProgram::set(const char* n, const float* m) const { glProgramUniformMatrix4fv(id_, loc(n), 1, GL_FALSE, m); }
void ShaderProgram::set2(const char* n, float x, float y) const { glProgramUniform2f(id_, loc(n), x, y); }
void ShaderProgram::set3(const char* n, float x, float y, float z) const { glProgramUniform3f(id_, loc(n), x, y, z); }
void ShaderProgram::set4(const char* n, float x, float y, float z, float w) const {
  glProgramUniform4f(id_, loc(n), x, y, z, w);
}
void ShaderProgram::setU2(const char* n, unsigned x, unsigned y) const { glProgramUniform2ui(id_, loc(n), x, y); }
void ShaderProgram::setU3(const char* n, unsigned x, unsigned y, unsigned z) const {
  glProgramUniform3ui(id_, loc(n), x, y, z);
}
void ShaderProgram::setI3v(const char* n, int count, const int* v) const {
  glProgramUniform3iv(id_, loc(n), count, v);
}
void ShaderProgram::set4v(const char* n, int count, const float* v) const {
  glProgramUniform4fv(id_, loc(n), count, v);
}

}  // namespace ml
