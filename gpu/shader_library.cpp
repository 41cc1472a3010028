#include "gpu/shader_library.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>

#include "gpu/embedded_files.h"
#include "gpu/gl_check.h"

namespace ft {
namespace {

// Embedded files first (their ids follow the generated table), registered ones after.
struct Registry {
  std::mutex mutex;
  std::vector<ShaderSource> files;  // id = index + 1

  Registry() {
    // FT_SHADER_DIR=<dir>: each embedded "shaders/<file>" is read from <dir>/<file>
    // instead when that file exists (edit-and-rerun of shaders without a rebuild;
    // scripts/mutation_test.py). common/ headers stay embedded: the C++ side
    // compiles them too, so a change there needs a rebuild anyway.
    const char* dir = std::getenv("FT_SHADER_DIR");
    for (std::size_t i = 0; i < detail::kEmbeddedFileCount; ++i) {
      const detail::EmbeddedFile& f = detail::kEmbeddedFiles[i];
      std::string text(f.text, f.size);
      std::string_view name(f.name);
      if (dir && *dir && name.rfind("shaders/", 0) == 0) {
        std::ifstream in(std::filesystem::path(dir) / std::string(name.substr(8)), std::ios::binary);
        if (in) text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      }
      files.push_back({f.name, std::move(text)});
    }
  }
  static Registry& get() {
    static Registry registry;
    return registry;
  }
};

// Collapses "." and ".." and maps "gpu/shaders/x" to "shaders/x".
std::string normalizePath(std::string_view path) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= path.size()) {
    std::size_t end = path.find('/', start);
    if (end == std::string_view::npos) end = path.size();
    std::string part(path.substr(start, end - start));
    if (part == "..") {
      if (!parts.empty()) parts.pop_back();
    } else if (!part.empty() && part != ".") {
      parts.push_back(part);
    }
    start = end + 1;
  }
  if (parts.size() >= 2 && parts[0] == "gpu" && parts[1] == "shaders") parts.erase(parts.begin());
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : "/") + p;
  return out;
}

// Index into Registry::files, or -1. Caller holds the mutex.
int findIndexLocked(Registry& r, std::string_view name) {
  std::string n = normalizePath(name);
  auto it = std::find_if(r.files.begin(), r.files.end(), [&](const ShaderSource& s) { return s.name == n; });
  if (it == r.files.end() && n.find('/') == std::string::npos) {
    std::string prefixed = "shaders/" + n;
    it = std::find_if(r.files.begin(), r.files.end(),
                      [&](const ShaderSource& s) { return s.name == prefixed; });
  }
  return it == r.files.end() ? -1 : static_cast<int>(it - r.files.begin());
}

bool endsWith(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

// For a preprocessor line "  #  name rest", returns name and sets rest; "" otherwise.
std::string_view directive(std::string_view line, std::string_view* rest) {
  std::size_t i = line.find_first_not_of(" \t");
  if (i == std::string_view::npos || line[i] != '#') return {};
  i = line.find_first_not_of(" \t", i + 1);
  if (i == std::string_view::npos) return {};
  std::size_t end = i;
  while (end < line.size() && (std::isalnum(static_cast<unsigned char>(line[end])) || line[end] == '_'))
    ++end;
  *rest = line.substr(end);
  return line.substr(i, end - i);
}

// The quoted (or <bracketed>) path of an #include; "" when malformed.
std::string includePath(std::string_view rest) {
  std::size_t open = rest.find_first_of("\"<");
  if (open == std::string_view::npos) return {};
  char close = rest[open] == '"' ? '"' : '>';
  std::size_t end = rest.find(close, open + 1);
  if (end == std::string_view::npos) return {};
  return std::string(rest.substr(open + 1, end - open - 1));
}

// Three-valued truth for preprocessor conditions: the resolver knows every
// #define seen so far (exactly, outside uncertain regions), so #ifdef/#ifndef and
// simple `#if defined(X) && !defined(Y)` evaluate exactly; anything else is Unknown.
enum class Truth { False, True, Unknown };

Truth truthNot(Truth a) { return a == Truth::Unknown ? a : (a == Truth::True ? Truth::False : Truth::True); }
Truth truthAnd(Truth a, Truth b) {
  if (a == Truth::False || b == Truth::False) return Truth::False;
  return (a == Truth::True && b == Truth::True) ? Truth::True : Truth::Unknown;
}
Truth truthOr(Truth a, Truth b) {
  if (a == Truth::True || b == Truth::True) return Truth::True;
  return (a == Truth::False && b == Truth::False) ? Truth::False : Truth::Unknown;
}

std::string firstIdentifier(std::string_view rest) {
  std::size_t i = rest.find_first_not_of(" \t");
  if (i == std::string_view::npos) return {};
  std::size_t end = i;
  while (end < rest.size() && (std::isalnum(static_cast<unsigned char>(rest[end])) || rest[end] == '_'))
    ++end;
  return std::string(rest.substr(i, end - i));
}

class MacroState {
 public:
  void define(const std::string& name, bool certain) { set(name, certain ? Truth::True : Truth::Unknown); }
  void undef(const std::string& name, bool certain) { set(name, certain ? Truth::False : Truth::Unknown); }
  Truth isDefined(const std::string& name) const {
    auto it = macros_.find(name);
    if (it != macros_.end()) return it->second;
    // Built-in and extension macros (GL_*, __VERSION__, ...) are the driver's business;
    // __cplusplus never is defined for GLSL.
    if (name == "__cplusplus") return Truth::False;
    if (name.rfind("GL_", 0) == 0 || name.rfind("__", 0) == 0 || name == "VULKAN") return Truth::Unknown;
    return Truth::False;
  }

  // Evaluates `defined X`, `defined(X)`, !, &&, ||, parentheses and 0/1.
  Truth evaluate(std::string_view expr) const {
    tokens_.clear();
    for (std::size_t i = 0; i < expr.size();) {
      char c = expr[i];
      if (c == ' ' || c == '\t') {
        ++i;
        continue;
      }
      if (expr.substr(i, 2) == "//") break;
      if (std::isalnum(static_cast<unsigned char>(c)) || c == '_') {
        std::size_t e = i;
        while (e < expr.size() && (std::isalnum(static_cast<unsigned char>(expr[e])) || expr[e] == '_')) ++e;
        tokens_.emplace_back(expr.substr(i, e - i));
        i = e;
      } else if (expr.substr(i, 2) == "&&" || expr.substr(i, 2) == "||") {
        tokens_.emplace_back(expr.substr(i, 2));
        i += 2;
      } else {
        tokens_.emplace_back(1, c);
        ++i;
      }
    }
    pos_ = 0;
    bool ok = true;
    Truth t = parseOr(ok);
    return ok && pos_ == tokens_.size() ? t : Truth::Unknown;
  }

 private:
  void set(const std::string& name, Truth t) { macros_[name] = t; }
  const std::string* peek() const { return pos_ < tokens_.size() ? &tokens_[pos_] : nullptr; }
  Truth parseOr(bool& ok) const {
    Truth t = parseAnd(ok);
    while (ok && peek() && *peek() == "||") {
      ++pos_;
      t = truthOr(t, parseAnd(ok));
    }
    return t;
  }
  Truth parseAnd(bool& ok) const {
    Truth t = parseUnary(ok);
    while (ok && peek() && *peek() == "&&") {
      ++pos_;
      t = truthAnd(t, parseUnary(ok));
    }
    return t;
  }
  Truth parseUnary(bool& ok) const {
    const std::string* tok = peek();
    if (!tok) {
      ok = false;
      return Truth::Unknown;
    }
    if (*tok == "!") {
      ++pos_;
      return truthNot(parseUnary(ok));
    }
    if (*tok == "(") {
      ++pos_;
      Truth t = parseOr(ok);
      if (!peek() || *peek() != ")") ok = false;
      ++pos_;
      return t;
    }
    if (*tok == "defined") {
      ++pos_;
      bool paren = peek() && *peek() == "(";
      if (paren) ++pos_;
      if (!peek()) {
        ok = false;
        return Truth::Unknown;
      }
      Truth t = isDefined(*peek());
      ++pos_;
      if (paren) {
        if (!peek() || *peek() != ")") ok = false;
        ++pos_;
      }
      return t;
    }
    ++pos_;
    if (*tok == "0") return Truth::False;
    if (*tok == "1") return Truth::True;
    return Truth::Unknown;  // macro values and arithmetic: left to the driver
  }

  std::map<std::string, Truth> macros_;
  mutable std::vector<std::string> tokens_;
  mutable std::size_t pos_ = 0;
};

// `#line` for line n of file id. Mesa reports source-string number 0 for most
// errors found after parsing (its YYLLOC_DEFAULT resets it), so the id also goes
// into the line number: id * kLineStride + n. mapShaderLog decodes both.
constexpr long kLineStride = 100000;
std::string lineDirective(int id, long n) {
  return "#line " + std::to_string(id * kLineStride + n) + " " + std::to_string(id) + "\n";
}

class Resolver {
 public:
  Resolver(Registry& r, const std::vector<std::string>& defines) : registry_(r) {
    for (const std::string& d : defines) macros_.define(firstIdentifier(d), true);
  }

  // Appends `name` (id-tagged) and, recursively, its includes; once per file.
  void emit(const std::string& name, const std::string& includedFrom, int includeLine) {
    int index = findIndexLocked(registry_, name);
    if (index < 0) {
      std::string where = includedFrom.empty()
                              ? ""
                              : " (included from " + includedFrom + ":" + std::to_string(includeLine) + ")";
      throw ShaderError("shader source not found: \"" + name + "\"" + where);
    }
    const ShaderSource& src = registry_.files[static_cast<std::size_t>(index)];
    // An include under an uncertain condition may be skipped by the driver, so it
    // does not count as done; the header's own guard keeps a repeat harmless.
    if (included_.count(src.name)) return;
    if (state() == Truth::True) included_.insert(src.name);
    const int id = index + 1;
    const std::size_t depth = conditions_.size();
    const std::string dir = src.name.substr(0, src.name.rfind('/') + 1);
    body_ += lineDirective(id, 1);
    std::string_view text = src.text;
    int lineNo = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
      std::size_t nl = text.find('\n', pos);
      std::string_view line =
          text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
      pos = nl == std::string_view::npos ? text.size() : nl + 1;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      ++lineNo;
      std::string_view rest;
      std::string_view d = directive(line, &rest);
      const std::string where = src.name + ":" + std::to_string(lineNo);
      trackConditional(d, rest, where);
      const Truth active = state();
      if (d == "include") {
        if (active == Truth::False) {
          body_ += "\n";  // skipped here: the C++-only #include <glm/...> etc.
          continue;
        }
        std::string path = includePath(rest);
        if (path.empty()) throw ShaderError(where + ": malformed #include: " + std::string(line));
        // Relative to the including file first, then from the repository root.
        std::string target = normalizePath(dir + path);
        if (findIndexLocked(registry_, target) < 0) target = normalizePath(path);
        emit(target, src.name, lineNo);
        body_ += lineDirective(id, lineNo + 1);
      } else if (d == "version") {
        body_ += "\n";  // the resolver writes the one #version
      } else if (d == "extension" && active == Truth::True) {
        // #extension must precede all declarations, so it moves up to the preamble.
        if (std::find(extensionLines_.begin(), extensionLines_.end(), std::string(line)) ==
            extensionLines_.end()) {
          extensionLines_.emplace_back(line);
          extensions_ += lineDirective(id, lineNo) + std::string(line) + "\n";
        }
        body_ += "\n";
      } else {
        if (d == "define" && active != Truth::False)
          macros_.define(firstIdentifier(rest), active == Truth::True);
        if (d == "undef" && active != Truth::False)
          macros_.undef(firstIdentifier(rest), active == Truth::True);
        body_.append(line);
        body_ += "\n";
      }
    }
    if (conditions_.size() != depth) throw ShaderError(src.name + ": unterminated #if/#ifdef at end of file");
  }

  std::string extensions() const { return extensions_; }
  std::string body() const { return body_; }

 private:
  struct Conditional {
    Truth current;  // of the branch being read
    Truth taken;    // whether an earlier branch was taken
  };

  // Combined truth of the enclosing branches.
  Truth state() const {
    Truth t = Truth::True;
    for (const Conditional& c : conditions_) t = truthAnd(t, c.current);
    return t;
  }

  void trackConditional(std::string_view d, std::string_view rest, const std::string& where) {
    if (d == "ifdef" || d == "ifndef" || d == "if") {
      Truth t = d == "if" ? macros_.evaluate(rest) : macros_.isDefined(firstIdentifier(rest));
      if (d == "ifndef") t = truthNot(t);
      conditions_.push_back({t, t});
    } else if (d == "elif" || d == "else") {
      if (conditions_.empty()) throw ShaderError(where + ": #" + std::string(d) + " without #if");
      Conditional& c = conditions_.back();
      Truth cond = d == "else" ? Truth::True : macros_.evaluate(rest);
      c.current = truthAnd(truthNot(c.taken), cond);
      c.taken = truthOr(c.taken, cond);
    } else if (d == "endif") {
      if (conditions_.empty()) throw ShaderError(where + ": #endif without #if");
      conditions_.pop_back();
    }
  }

  Registry& registry_;
  MacroState macros_;
  std::vector<Conditional> conditions_;
  std::set<std::string> included_;
  std::vector<std::string> extensionLines_;
  std::string extensions_;
  std::string body_;
};

// "file:line" for a reported (source number, line), or "" when it is not ours.
std::string sourceLocation(const std::vector<std::string>& names, const std::string& sourceText,
                           const std::string& lineText) {
  long source = std::stol(sourceText);
  long line = std::stol(lineText);
  long id = line >= kLineStride ? line / kLineStride : source;
  if (line >= kLineStride) line %= kLineStride;
  if (id == 0) return "<preamble>:" + std::to_string(line);
  if (id < 0 || static_cast<std::size_t>(id) > names.size()) return {};
  return names[static_cast<std::size_t>(id) - 1] + ":" + std::to_string(line);
}

std::string joinDefines(const std::vector<std::string>& defines) {
  if (defines.empty()) return "no defines";
  std::string s = "defines:";
  for (const std::string& d : defines) s += " " + d;
  return s;
}

void labelObject(GLenum type, GLuint id, const std::string& label) {
  std::string l = label.substr(0, 200);  // GL_MAX_LABEL_LENGTH is at least 256
  glObjectLabel(type, id, static_cast<GLsizei>(l.size()), l.c_str());
}

}  // namespace

std::optional<ShaderSource> findShaderSource(std::string_view name) {
  Registry& r = Registry::get();
  std::lock_guard lock(r.mutex);
  int index = findIndexLocked(r, name);
  if (index < 0) return std::nullopt;
  return r.files[static_cast<std::size_t>(index)];
}

std::vector<std::string> shaderSourceNames() {
  Registry& r = Registry::get();
  std::lock_guard lock(r.mutex);
  std::vector<std::string> names;
  for (const ShaderSource& s : r.files) names.push_back(s.name);
  return names;
}

int shaderSourceId(std::string_view name) {
  Registry& r = Registry::get();
  std::lock_guard lock(r.mutex);
  int index = findIndexLocked(r, name);
  return index < 0 ? -1 : index + 1;
}

void registerShaderSourceForTest(std::string name, std::string text) {
  Registry& r = Registry::get();
  std::lock_guard lock(r.mutex);
  name = normalizePath(name);
  for (ShaderSource& s : r.files) {
    if (s.name == name) {
      s.text = std::move(text);
      return;
    }
  }
  r.files.push_back({std::move(name), std::move(text)});
}

GLenum shaderStageFromName(std::string_view file) {
  if (endsWith(file, ".vert.glsl")) return GL_VERTEX_SHADER;
  if (endsWith(file, ".tesc.glsl")) return GL_TESS_CONTROL_SHADER;
  if (endsWith(file, ".tese.glsl")) return GL_TESS_EVALUATION_SHADER;
  if (endsWith(file, ".geom.glsl")) return GL_GEOMETRY_SHADER;
  if (endsWith(file, ".frag.glsl")) return GL_FRAGMENT_SHADER;
  if (endsWith(file, ".comp.glsl")) return GL_COMPUTE_SHADER;
  return 0;
}

const char* shaderStageShortName(std::string_view file) {
  for (const char* s : {"vert", "tesc", "tese", "geom", "frag", "comp"})
    if (endsWith(file, std::string(".") + s + ".glsl")) return s;
  return "";
}

std::string resolveShader(std::string_view file, const std::vector<std::string>& defines) {
  Registry& r = Registry::get();
  std::lock_guard lock(r.mutex);
  std::string head = "#version 450 core\n";
  for (std::string d : defines) {
    std::size_t eq = d.find('=');
    if (eq != std::string::npos) d[eq] = ' ';
    if (d.empty() || d.find('\n') != std::string::npos) throw ShaderError("bad shader define: \"" + d + "\"");
    head += "#define " + d + "\n";
  }
  Resolver resolver(r, defines);
  // prelude.h first, as its header comment promises; the common headers include it anyway.
  resolver.emit("common/prelude.h", {}, 0);
  resolver.emit(std::string(file), {}, 0);
  return head + resolver.extensions() + resolver.body();
}

std::string mapShaderLog(std::string_view log) {
  std::vector<std::string> names = shaderSourceNames();
  static const std::regex mesa(R"(^(\d+):(\d+)\((\d+)\): (.*)$)");
  static const std::regex nvidia(R"(^(\d+)\((\d+)\) : (.*)$)");
  static const std::regex glslang(R"(^(ERROR|WARNING): (\d+):(\d+): (.*)$)");
  std::string out;
  std::istringstream in{std::string(log)};
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    std::string mapped;
    if (std::regex_match(line, m, mesa)) {
      std::string loc = sourceLocation(names, m[1], m[2]);
      if (!loc.empty()) mapped = loc + ":" + m[3].str() + ": " + m[4].str();
    } else if (std::regex_match(line, m, nvidia)) {
      std::string loc = sourceLocation(names, m[1], m[2]);
      if (!loc.empty()) mapped = loc + ": " + m[3].str();
    } else if (std::regex_match(line, m, glslang)) {
      std::string loc = sourceLocation(names, m[2], m[3]);
      if (!loc.empty()) mapped = m[1].str() + ": " + loc + ": " + m[4].str();
    }
    out += (mapped.empty() ? line : mapped) + "\n";
  }
  return out;
}

GLuint buildProgram(const std::vector<std::string>& stageFiles, const std::vector<std::string>& defines,
                    const std::vector<std::string>& xfbVaryings, GLenum xfbMode) {
  if (stageFiles.empty()) throw ShaderError("buildProgram: no stage files");
  std::vector<GLuint> shaders;
  GLuint program = glCreateProgram();
  auto cleanup = [&] {
    for (GLuint s : shaders) glDeleteShader(s);
    shaders.clear();
  };
  std::string files;
  try {
    for (const std::string& file : stageFiles) {
      files += (files.empty() ? "" : " + ") + file;
      GLenum stage = shaderStageFromName(file);
      if (stage == 0)
        throw ShaderError(file + ": no stage suffix (.vert/.tesc/.tese/.geom/.frag/.comp.glsl)");
      std::string text = resolveShader(file, defines);
      GLuint shader = glCreateShader(stage);
      shaders.push_back(shader);
      const char* ptr = text.c_str();
      glShaderSource(shader, 1, &ptr, nullptr);
      glCompileShader(shader);
      GLint ok = GL_FALSE, logLength = 0;
      glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
      glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &logLength);
      if (!ok) {
        std::string log(static_cast<std::size_t>(std::max(logLength, 1)), '\0');
        glGetShaderInfoLog(shader, logLength, nullptr, log.data());
        log.resize(std::char_traits<char>::length(log.c_str()));
        throw ShaderError("compiling " + file + " (" + joinDefines(defines) + ") failed:\n" +
                          mapShaderLog(log));
      }
      labelObject(GL_SHADER, shader, file);
      glAttachShader(program, shader);
    }
    if (!xfbVaryings.empty()) {
      std::vector<const char*> names;
      for (const std::string& v : xfbVaryings) names.push_back(v.c_str());
      glTransformFeedbackVaryings(program, static_cast<GLsizei>(names.size()), names.data(), xfbMode);
    }
    glLinkProgram(program);
    GLint ok = GL_FALSE, logLength = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &logLength);
    if (!ok) {
      std::string log(static_cast<std::size_t>(std::max(logLength, 1)), '\0');
      glGetProgramInfoLog(program, logLength, nullptr, log.data());
      log.resize(std::char_traits<char>::length(log.c_str()));
      throw ShaderError("linking " + files + " (" + joinDefines(defines) + ") failed:\n" + mapShaderLog(log));
    }
    labelObject(GL_PROGRAM, program, files);
    for (GLuint s : shaders) glDetachShader(program, s);
    cleanup();
    glCheck(("buildProgram(" + files + ")").c_str());
  } catch (...) {
    cleanup();
    glDeleteProgram(program);
    throw;
  }
  return program;
}

}  // namespace ft
