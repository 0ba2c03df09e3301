// exr_compare A.exr [REF.exr]: prints the mean of each channel of A and, with a reference,
// the error of A against it (RMSE, relMSE with the usual 1e-2 guard in the denominator, and
// the fraction of pixels within 1e-3 relative). Used by the benchmarks and by hand.
#include <cmath>
#include <cstdio>

#include "host/film/image_io.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: exr_compare A.exr [REF.exr]\n");
    return 2;
  }
  try {
    aw::Image a = aw::read_exr(argv[1]);
    double m[3] = {0, 0, 0};
    size_t n = size_t(a.width) * a.height;
    for (size_t p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c) m[c] += a.rgb[p * 3 + c];
    std::printf("%s: %dx%d spp %d mean R %.6f G %.6f B %.6f\n", argv[1], a.width, a.height, a.int_attrs["spp"],
                m[0] / n, m[1] / n, m[2] / n);
    if (argc > 2) {
      aw::Image r = aw::read_exr(argv[2]);
      if (r.width != a.width || r.height != a.height) {
        std::fprintf(stderr, "size mismatch\n");
        return 2;
      }
      double se = 0.0, rel = 0.0;
      for (size_t i = 0; i < a.rgb.size(); ++i) {
        double d = double(a.rgb[i]) - double(r.rgb[i]);
        se += d * d;
        rel += d * d / (double(r.rgb[i]) * r.rgb[i] + 1e-2);
      }
      aw::ImageDiff d = aw::compare_images(a, r, 1e-3, 1e-4);
      std::printf("vs %s: RMSE %.6g relMSE %.6g within1e-3 %.4f%%\n", argv[2], std::sqrt(se / a.rgb.size()),
                  rel / a.rgb.size(), d.frac_pixels_within * 100);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "exr_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
