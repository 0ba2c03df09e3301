// From: FREE (a slot and a batch-local job) / To: RAY.
// Starts a camera path: pinhole camera, pixel jittered uniformly within its footprint.
#ifndef AW_INTEGRATOR_GENERATE_CAMERA_RAY_H
#define AW_INTEGRATOR_GENERATE_CAMERA_RAY_H

#include "common/rng.h"
#include "integrator/aov.h"
#include "integrator/path_state.h"
#include "types/scene.h"

AW_FN void generate_camera_ray(PathRef ps, const RenderParams* rp, uint job) {
  uint npix = rp->win_w * rp->win_h;
  // Batch-local job -> (film pixel, sample), see RenderParams. (batch_pixel < npix, so the sum
  // cannot overflow for any batch that fits in memory.) The film pixel is one of the window's;
  // the path carries the frame's pixel index, which the sampler sees, so a window's pixels
  // get exactly the random numbers they get in the whole frame.
  uint k = rp->batch_pixel + job;
  uint film_px = k % npix;
  uint sample = rp->batch_sample + k / npix;
  uint px = rp->win_x0 + film_px % rp->win_w, py = rp->win_y0 + film_px / rp->win_w;
  uint pixel = py * rp->width + px;

  float2 j = rng_2d(rp_sampler(rp), pixel, sample, 0u, AW_DIM_CAMERA);
  float sx = (2.0f * ((float)px + j.x) / (float)rp->width - 1.0f) * rp->tan_half_fov * rp->aspect;
  float sy = (1.0f - 2.0f * ((float)py + j.y) / (float)rp->height) * rp->tan_half_fov;
  float3 d = normalize(load_f3p(rp->cam_forward) + sx * load_f3p(rp->cam_right) + sy * load_f3p(rp->cam_up));

  ps_set_ray(ps, load_f3p(rp->cam_origin), d);
  ps_set_throughput(ps, make_float3(1.0f, 1.0f, 1.0f));
  PS_F(ps, rad_r) = 0.0f;
  PS_F(ps, rad_g) = 0.0f;
  PS_F(ps, rad_b) = 0.0f;
  PS_F(ps, bsdf_pdf) = 0.0f;
  PS_U(ps, job) = job;
  PS_U(ps, pixel) = pixel;
  PS_U(ps, sample) = sample;
  PS_U(ps, bounce) = 0u;
  PS_U(ps, flags) = 0u;
  PS_F(ps, emit_scale) = 1.0f;
  PS_F(ps, eta_scale) = 1.0f;
  PS_U(ps, depths) = 0u;
  PS_U(ps, medium) = AW_NONE;  // cameras start outside every object
  // The ray cone of a pixel: zero width at the pinhole, the pixel's angle as its spread
  // (Akenine-Möller et al. 2019, Ray Tracing Gems ch. 20, Sec. 20.3.4: gamma_0 from the
  // vertical field of view and the image height).
  PS_F(ps, cone_w) = 0.0f;
  PS_F(ps, cone_s) = 2.0f * rp->tan_half_fov / (float)rp->height;
  aov_begin(ps, rp);
}

#endif
