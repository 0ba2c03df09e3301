#include "host/cl/kernel_source.h"

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace aw {

std::string default_kernel_dir() {
  if (const char* d = std::getenv("ARCHWAVE_KERNEL_DIR"); d && *d) return d;
#ifdef ARCHWAVE_KERNELS_FROM_DISK_DEFAULT
  return ARCHWAVE_SOURCE_KERNEL_DIR;
#else
  return "";
#endif
}

namespace {

std::string read_kernel_file(const std::string& rel, const std::string& dir) {
  if (dir.empty()) {
    for (const EmbeddedKernelFile* f = kEmbeddedKernelFiles; f->path; ++f)
      if (rel == f->path) return f->text;
    throw std::runtime_error("kernel source not found in the embedded set: kernels/" + rel);
  }
  std::ifstream in(dir + "/" + rel, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read kernel source " + dir + "/" + rel);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void expand(const std::string& rel, const std::string& dir, std::set<std::string>& seen, std::string& out) {
  if (!seen.insert(rel).second) return;  // every kernel header has a guard; include once
  std::istringstream in(read_kernel_file(rel, dir));
  out += "#line 1 \"kernels/" + rel + "\"\n";
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    size_t p = line.find_first_not_of(" \t");
    if (p != std::string::npos && line.compare(p, 8, "#include") == 0) {
      size_t q0 = line.find('"', p);
      size_t q1 = q0 == std::string::npos ? q0 : line.find('"', q0 + 1);
      if (q1 != std::string::npos) {
        std::string inc = line.substr(q0 + 1, q1 - q0 - 1);
        // State templates are X-macro lists included several times on purpose.
        if (inc.find("state_template.h") != std::string::npos) {
          std::string body = read_kernel_file(inc, dir);
          out += "#line 1 \"kernels/" + inc + "\"\n" + body + "\n";
        } else {
          expand(inc, dir, seen, out);
        }
        out += "#line " + std::to_string(n + 1) + " \"kernels/" + rel + "\"\n";
        continue;
      }
    }
    out += line;
    out += '\n';
  }
}

}  // namespace

std::string assemble_kernel_source(const std::string& entry, const std::string& kernel_dir) {
  std::set<std::string> seen;
  std::string out;
  expand(entry, kernel_dir, seen, out);
  return out;
}

}  // namespace aw
