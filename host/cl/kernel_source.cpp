#include "host/cl/kernel_source.h"

#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

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
  // Every kernel header has a guard: include once. The text goes where the first #include
  // of it is, so a header first included inside an #if block (as kernels/material/
  // architectural.h's one-path-only headers are, under #if AW_LANES == 1) is absent where the
  // block is off: code outside such a block includes what it needs itself, before the block.
  if (!seen.insert(rel).second) return;
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

namespace {

// Where every raw line of an assembled source comes from ("" for the `#line` markers and
// anything before the first one), read off its markers.
std::vector<std::string> source_locations(const std::string& source) {
  // `#line N "file"`: the next raw line is line N of file (C11 6.10.4).
  static const std::regex marker(R"re(^#line (\d{1,9}) "([^"]*)"\s*$)re");
  std::vector<std::string> out;
  std::string file;
  long next = 1;  // the line number in `file` of the next raw line
  std::istringstream in(source);
  std::string text;
  std::smatch m;
  while (std::getline(in, text)) {
    if (std::regex_match(text, m, marker)) {
      out.emplace_back();
      next = std::stol(m[1].str());
      file = m[2].str();
    } else {
      out.push_back(file.empty() ? std::string() : file + ":" + std::to_string(next));
      ++next;
    }
  }
  return out;
}

}  // namespace

std::string assembled_source_location(const std::string& source, long line) {
  std::vector<std::string> where = source_locations(source);
  return line >= 1 && size_t(line) <= where.size() ? where[size_t(line - 1)] : std::string();
}

std::string annotate_build_log(const std::string& source, const std::string& log) {
  // "<kernel>:LINE:COL" or "<kernel>:LINE": a compiler's name for a source it was given as a
  // string. A name in angle brackets never is one of ours (ours are kernels/<file>).
  static const std::regex position(R"((<[A-Za-z_ ]+>):(\d{1,9})(:(\d{1,9}))?)");
  std::vector<std::string> where;  // read once, at the first position
  std::string out;
  size_t last = 0;
  for (auto it = std::sregex_iterator(log.begin(), log.end(), position); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    if (where.empty()) where = source_locations(source);
    const long line = std::stol(m[2].str());
    out.append(log, last, size_t(m.position(0)) - last);
    out += m.str(0);
    if (line >= 1 && size_t(line) <= where.size() && !where[size_t(line - 1)].empty())
      out += " [" + where[size_t(line - 1)] + (m[4].matched ? ":" + m[4].str() : "") + "]";
    last = size_t(m.position(0) + m.length(0));
  }
  out.append(log, last, std::string::npos);
  return out;
}

}  // namespace aw
