// From: FREE (a slot and a job of the batch ring) / To: RAY.
// Starts a camera path: pinhole camera, pixel jittered uniformly within its footprint.
#ifndef AW_INTEGRATOR_GENERATE_CAMERA_RAY_H
#define AW_INTEGRATOR_GENERATE_CAMERA_RAY_H

#include "common/features.h"
#include "common/rng.h"
#include "integrator/aov.h"
#include "integrator/path_state.h"
#include "types/scene.h"

// Written on lanes (common/lanes.h): at W = 1 one path, as the host's scalar path and the
// queue launch run it; at W > 1 the W consecutive slots of a lane kernel (kernels_lanes.cl,
// kernel_regenerate_lanes), each live lane with its own job.
AW_FN void generate_camera_ray(PathRef ps, const RenderParams* rp, luint job) {
  uint npix = rp->win_w * rp->win_h;
  // The job's index in the batch ring -> (film pixel, sample), see RenderParams. (batch_pixel
  // < 2 npix + the ring's half size, so the sum cannot overflow for any ring that fits in memory.) The film pixel is one of the window's;
  // the path carries the frame's pixel index, which the sampler sees, so a window's pixels
  // get exactly the random numbers they get in the whole frame.
  luint k = rp->batch_pixel + job;
  luint film_px = k % npix;
  luint sample = rp->batch_sample + k / npix;
  luint px = rp->win_x0 + film_px % rp->win_w, py = rp->win_y0 + film_px / rp->win_w;
  luint pixel = py * rp->width + px;

  lfloat2 j = rng_2d(rp_sampler(rp), pixel, sample, (luint)(0u), AW_DIM_CAMERA);
  lfloat sx = (2.0f * (L_TO_FLOAT(px) + j.x) / (float)rp->width - 1.0f) * rp->tan_half_fov * rp->aspect;
  lfloat sy = (1.0f - 2.0f * (L_TO_FLOAT(py) + j.y) / (float)rp->height) * rp->tan_half_fov;
  lfloat3 d = l3_normalize(l3_add(l3_add(l3_bcast(load_f3p(rp->cam_forward)), l3_scale(l3_bcast(load_f3p(rp->cam_right)), sx)),
                                  l3_scale(l3_bcast(load_f3p(rp->cam_up)), sy)));

  ps_set_ray(ps, l3_bcast(load_f3p(rp->cam_origin)), d);
  ps_set_throughput(ps, l3_splat((lfloat)(1.0f)));
  PS_SET_F(ps, rad_r, (lfloat)(0.0f));
  PS_SET_F(ps, rad_g, (lfloat)(0.0f));
  PS_SET_F(ps, rad_b, (lfloat)(0.0f));
  PS_SET_F(ps, bsdf_pdf, (lfloat)(0.0f));
  PS_SET_U(ps, job, job);
  PS_SET_U(ps, pixel, pixel);
  PS_SET_U(ps, sample, sample);
  PS_SET_U(ps, bounce, (luint)(0u));
  PS_SET_U(ps, flags, (luint)(0u));
  PS_SET_F(ps, emit_scale, (lfloat)(1.0f));
  // The fields below are read only by the features named beside them; a build without those
  // features neither reads nor writes them (design principle 4, docs/design.md: kernels model
  // only what the scene requires; a camera path on lanes writes a cache line per field per 16
  // paths, docs/performance.md, "State fields, sorted hits in slot order, accumulate on lanes").
  if (AW_FEAT_REFRACTION) PS_SET_F(ps, eta_scale, (lfloat)(1.0f));  // Russian roulette's eta^2
  if (AW_FEAT_REFLECTION | AW_FEAT_REFRACTION) PS_SET_U(ps, depths, (luint)(0u));  // trace depths
  if (AW_FEAT_FOG) PS_SET_U(ps, medium, (luint)(AW_NONE));  // cameras start outside every object
  // The ray cone of a pixel, for texture filtering: zero width at the pinhole, the pixel's
  // angle as its spread (Akenine-Möller et al. 2019, Ray Tracing Gems ch. 20, Sec. 20.3.4:
  // gamma_0 from the vertical field of view and the image height).
  if (AW_FEAT_TEXTURE) {
    PS_SET_F(ps, cone_w, (lfloat)(0.0f));
    PS_SET_F(ps, cone_s, (lfloat)(2.0f * rp->tan_half_fov / (float)rp->height));
  }
#if AW_LANES == 1
  aov_begin(ps, rp);  // the lane program is built only for renders without AOVs
#endif
}

#endif
