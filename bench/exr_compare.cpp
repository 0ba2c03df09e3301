// exr_compare [--json] A.exr [REF.exr]: prints the mean of each channel of A and, with a
// reference, the error of A against it (RMSE, relMSE with the usual 1e-2 guard in the
// denominator, and the fraction of pixels within 1e-3 relative). Used by the benchmarks and
// by hand. --json prints one JSON object instead (read by scripts/bench_suite.py):
//   {"file", "width", "height", "spp", "mean": [r, g, b],
//    "reference", "rmse", "relmse", "within_1e-3"}   (the last four only with REF.exr)
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <nlohmann/json.hpp>

#include "host/film/image_io.h"

int main(int argc, char** argv) {
  bool json = false;
  const char* files[2] = {nullptr, nullptr};
  int nfiles = 0;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--json") == 0) json = true;
    else if (nfiles < 2) files[nfiles++] = argv[i];
    else nfiles = 3;
  }
  if (nfiles < 1 || nfiles > 2) {
    std::fprintf(stderr, "usage: exr_compare [--json] A.exr [REF.exr]\n");
    return 2;
  }
  try {
    aw::Image a = aw::read_exr(files[0]);
    double m[3] = {0, 0, 0};
    size_t n = size_t(a.width) * a.height;
    for (size_t p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c) m[c] += a.rgb[p * 3 + c];
    for (double& v : m) v /= double(n ? n : 1);
    nlohmann::json out = {{"file", files[0]},
                          {"width", a.width},
                          {"height", a.height},
                          {"spp", a.int_attrs["spp"]},
                          {"mean", {m[0], m[1], m[2]}}};
    if (!json)
      std::printf("%s: %dx%d spp %d mean R %.6f G %.6f B %.6f\n", files[0], a.width, a.height, a.int_attrs["spp"],
                  m[0], m[1], m[2]);
    if (files[1]) {
      aw::Image r = aw::read_exr(files[1]);
      if (r.width != a.width || r.height != a.height) {
        std::fprintf(stderr, "exr_compare: size mismatch: %s is %dx%d, %s is %dx%d\n", files[0], a.width, a.height,
                     files[1], r.width, r.height);
        return 2;
      }
      double se = 0.0, rel = 0.0;
      for (size_t i = 0; i < a.rgb.size(); ++i) {
        double d = double(a.rgb[i]) - double(r.rgb[i]);
        se += d * d;
        rel += d * d / (double(r.rgb[i]) * r.rgb[i] + 1e-2);
      }
      const double count = double(a.rgb.empty() ? 1 : a.rgb.size());
      aw::ImageDiff d = aw::compare_images(a, r, 1e-3, 1e-4);
      out["reference"] = files[1];
      out["rmse"] = std::sqrt(se / count);
      out["relmse"] = rel / count;
      out["within_1e-3"] = d.frac_pixels_within;
      if (!json)
        std::printf("vs %s: RMSE %.6g relMSE %.6g within1e-3 %.4f%%\n", files[1], std::sqrt(se / count), rel / count,
                    d.frac_pixels_within * 100);
    }
    if (json) std::cout << out.dump() << "\n";
  } catch (const std::exception& e) {
    std::fprintf(stderr, "exr_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
