#include "host/cl/kernel_cache.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "host/film/image_io.h"

namespace aw {

namespace {

constexpr const char* kMagic = "archwave-kernel-binary 1";

}  // namespace

uint64_t fnv1a64(const void* data, size_t n, uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ull;
  }
  return h;
}

std::string hex16(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)v);
  return buf;
}

std::string kernel_cache_dir() {
  if (const char* v = std::getenv("ARCHWAVE_KERNEL_CACHE"); v && *v) {
    std::string s(v);
    if (s == "0" || s == "off") return "";
    return s;
  }
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/archwave/kernels";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/archwave/kernels";
  return "";
}

KernelCache::KernelCache(std::string dir, const std::string& key) : dir_(std::move(dir)) {
  if (dir_.empty()) return;
  // Two independent 64-bit hashes of the key: one names the file, the other is checked inside
  // it, so two keys would have to collide in both to be confused.
  path_ = dir_ + "/" + hex16(fnv1a64(key)) + ".bin";
  check_ = fnv1a64(key, 0x84222325cbf29ce4ull);
}

bool KernelCache::load(std::vector<unsigned char>* binary) const {
  if (!enabled()) return false;
  std::ifstream in(path_, std::ios::binary);
  if (!in) return false;
  std::string header;
  if (!std::getline(in, header)) return false;
  std::istringstream h(header);
  std::string magic1, magic2, check, checksum;
  unsigned long long size = 0;
  if (!(h >> magic1 >> magic2 >> check >> size >> checksum)) return false;
  if (magic1 + " " + magic2 != kMagic || check != hex16(check_)) return false;
  std::vector<unsigned char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (data.size() != size || size == 0 || hex16(fnv1a64(data.data(), data.size())) != checksum) return false;
  *binary = std::move(data);
  return true;
}

std::string KernelCache::store(const std::vector<unsigned char>& binary) const {
  if (!enabled() || binary.empty()) return "";
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) return "cannot create " + dir_ + ": " + ec.message();
  std::string text = std::string(kMagic) + " " + hex16(check_) + " " + std::to_string(binary.size()) + " " +
                     hex16(fnv1a64(binary.data(), binary.size())) + "\n";
  text.append(reinterpret_cast<const char*>(binary.data()), binary.size());
  // A name of this process's own, renamed into place: write_text_file's temporary is the
  // target's name plus ".tmp", which two processes storing the same program would share.
  std::string mine = path_ + "." + std::to_string(::getpid());
  try {
    write_text_file("the kernel binary cache", mine, text);
  } catch (const std::exception& e) {
    return e.what();
  }
  if (std::rename(mine.c_str(), path_.c_str()) != 0) {
    std::remove(mine.c_str());
    return "cannot rename " + mine + " to " + path_;
  }
  return "";
}

}  // namespace aw
