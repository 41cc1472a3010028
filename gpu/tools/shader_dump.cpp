// ft_shader_dump — writes every resolved shader stage file (gpu/shaders/*.glsl
// with a stage suffix), as the GL driver would receive it, for offline checks
// (glslangValidator, see cmake/ValidateShaders.cmake).
//
//   ft_shader_dump --out DIR [--define NAME[=VALUE]]...
//       DIR/plain/<file> without defines, DIR/<NAME>/<file> once per --define,
//       DIR/sources.txt: the source-string ids used in #line.
//   ft_shader_dump --map-log FILE
//       prints FILE (a compiler log) with "<id>:<line>" mapped to file names.
//   ft_shader_dump --list
//       prints the embedded file names.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "gpu/shader_library.h"

namespace {

int usage() {
  std::cerr << "usage: ft_shader_dump --out DIR [--define NAME[=VALUE]]...\n"
               "       ft_shader_dump --map-log FILE\n"
               "       ft_shader_dump --list\n";
  return 2;
}

void writeFile(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string dirNameFor(const std::string& define) {
  std::string s;
  for (char c : define) s += (std::isalnum(static_cast<unsigned char>(c)) || c == '_') ? c : '_';
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string outDir, mapLog;
  bool list = false;
  std::vector<std::string> defines;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--out" && i + 1 < argc)
      outDir = argv[++i];
    else if (a == "--define" && i + 1 < argc)
      defines.push_back(argv[++i]);
    else if (a == "--map-log" && i + 1 < argc)
      mapLog = argv[++i];
    else if (a == "--list")
      list = true;
    else
      return usage();
  }
  try {
    if (list) {
      for (const std::string& n : ft::shaderSourceNames()) std::cout << n << "\n";
      return 0;
    }
    if (!mapLog.empty()) {
      std::ifstream in(mapLog, std::ios::binary);
      if (!in) throw std::runtime_error("cannot read " + mapLog);
      std::stringstream s;
      s << in.rdbuf();
      std::cout << ft::mapShaderLog(s.str());
      return 0;
    }
    if (outDir.empty()) return usage();
    std::vector<std::string> stageFiles;
    std::string ids;
    for (const std::string& n : ft::shaderSourceNames()) {
      ids += std::to_string(ft::shaderSourceId(n)) + " " + n + "\n";
      if (n.rfind("shaders/", 0) == 0 && ft::shaderStageFromName(n) != 0) stageFiles.push_back(n);
    }
    std::filesystem::path root(outDir);
    writeFile(root / "sources.txt", ids);
    int written = 0;
    for (const std::string& file : stageFiles) {
      std::string base = file.substr(file.rfind('/') + 1);
      writeFile(root / "plain" / base, ft::resolveShader(file, {}));
      ++written;
      for (const std::string& d : defines) {
        writeFile(root / dirNameFor(d) / base, ft::resolveShader(file, {d}));
        ++written;
      }
    }
    std::cout << "ft_shader_dump: wrote " << written << " files (" << stageFiles.size() << " stages x "
              << defines.size() + 1 << " variants) to " << outDir << "\n";
  } catch (const std::exception& e) {
    std::cerr << "ft_shader_dump: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
