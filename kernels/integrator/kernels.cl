// The wavefront's OpenCL entry points. Each is a thin wrapper: index -> slot -> the shared
// stage function (kernels/integrator/*.h, the same code the host scalar path runs through
// megakernel.h) -> aggregated queue appends. The scheduling rule is in integrator/queues.h;
// every entry point takes the one argument list of integrator/stage_args.h.
//
// Queues live in one buffer: queue q occupies queues[q * pool .. q * pool + pool).
// Launch contract (host/render/wavefront.cpp): an explicit local size AW_WG (>= AW_Q_COUNT)
// and a global size padded up to a multiple of it; `count` is the real number of items.
// Every work-item of a group reaches the appends (they contain barriers), so the bounds
// check only masks work.
#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#include "integrator/accumulate.h"
#include "integrator/aov.h"
#include "integrator/ambient_occlusion.h"
#include "integrator/classify_hit.h"
#include "integrator/film.h"
#include "integrator/generate_camera_ray.h"
#include "integrator/intersect_closest.h"
#include "integrator/intersect_shadow.h"
#include "integrator/path_state.h"
#include "integrator/queues.h"
#include "integrator/shade_surface.h"
#include "integrator/stage_args.h"
#include "material/lobe_list.h"

#include "integrator/stage_kernel.h"

AW_STAGE_KERNEL_SCALAR(kernel_regenerate) {
  AW_APPEND_LOCALS;
  uint i = get_global_id(0);
  uint q = AW_Q_COUNT;
  uint slot = 0u;
  if (i < count) {
    // The last `count` entries of the FREE queue (counters[AW_Q_FREE] of them, which this
    // launch does not change), so that the entries left over stay at its front for the next
    // launch: the batch ring starts the next batch in the same iteration (host/render/wavefront.cpp).
    slot = AW_QUEUE(AW_Q_FREE)[counters[AW_Q_FREE] - count + i];
    generate_camera_ray(AW_STAGE_PATH(slot), &rp, job_start + i);
    q = AW_Q_RAY;
  }
  AW_APPEND(q, slot);
}

AW_STAGE_KERNEL_SCALAR(kernel_intersect_closest) {
  uint slot = 0u;
  if (!AW_STAGE_SLOT(AW_Q_RAY, slot)) return;
  intersect_closest(AW_STAGE_PATH(slot), AW_STAGE_SCENE, &rp);
}

AW_STAGE_KERNEL_SCALAR(kernel_classify_hit) {
  AW_APPEND_LOCALS;
  uint slot = 0u;
  uint q = AW_Q_COUNT;
  if (AW_STAGE_SLOT(AW_Q_RAY, slot)) q = (uint)classify_hit(AW_STAGE_PATH(slot), AW_STAGE_SCENE, &rp);
  AW_APPEND(q, slot);
}

// One shading kernel per lobe of the lobe list (material/lobe_list.h), each shade_surface with
// its own constant lobe id. A lobe this build lacks keeps its entry point, empty: the host
// never launches it (FeatureSet::lobe), and the per-hit check keeps paths out of its queue.
#define AW_SHADE_KERNEL(ID, name, FEATURE, TRAITS)                                       \
  AW_STAGE_KERNEL(kernel_shade_##name) {                                                 \
    AW_APPEND_LOCALS;                                                                    \
    uint slot = 0u;                                                                      \
    uint q = AW_Q_COUNT, qs = AW_Q_COUNT;                                                \
    if (AW_FEAT_##FEATURE && AW_STAGE_SLOT(AW_Q_LOBE + AW_LID_##ID, slot)) {             \
      PathRef ps = AW_STAGE_PATH(slot);                                                  \
      q = (uint)shade_surface(ps, AW_STAGE_SCENE, &rp, (uint)AW_LID_##ID);               \
      if (PS_U(ps, flags) & AW_PATH_HAS_SHADOW) qs = AW_Q_SHADOW;                        \
    }                                                                                    \
    AW_APPEND(qs, slot);                                                                 \
    AW_APPEND(q, slot);                                                                  \
  }
AW_LOBE_LIST(AW_SHADE_KERNEL)
#undef AW_SHADE_KERNEL

// Ambient occlusion (integrator/ambient_occlusion.h): it traces rays, so it is built scalar
// on Intel's runtime like the other ray stages. Empty in builds without AO.
AW_STAGE_KERNEL_SCALAR(kernel_ambient_occlusion) {
  AW_APPEND_LOCALS;
  uint slot = 0u;
  uint q = AW_Q_COUNT;
  if (AW_FEAT_AO && AW_STAGE_SLOT(AW_Q_AO, slot)) q = (uint)ambient_occlusion(AW_STAGE_PATH(slot), AW_STAGE_SCENE, &rp);
  AW_APPEND(q, slot);
}

AW_STAGE_KERNEL_SCALAR(kernel_intersect_shadow) {
  uint slot = 0u;
  if (!AW_STAGE_SLOT(AW_Q_SHADOW, slot)) return;
  intersect_shadow(AW_STAGE_PATH(slot), AW_STAGE_SCENE, &rp);
}

// A split path (integrator/split.h) goes back to its first-hit lobe queue until its last
// split ends; only then does the job's value (the mean of the splits) reach `samples`, and the
// job counts as finished in its half of the batch ring (`job_start`: the half's size;
// AW_C_FINISHED, integrator/queues.h), counted with the group's appends.
AW_STAGE_KERNEL_SCALAR(kernel_accumulate) {
  AW_APPEND_LOCALS;
  uint slot = 0u;
  uint q = AW_Q_COUNT;
  uint finished = AW_C_COUNT;  // none
  if (AW_STAGE_SLOT(AW_Q_DONE, slot)) {
    PathRef ps = AW_STAGE_PATH(slot);
    float3 l;
    uint events;
    q = (uint)accumulate_path(ps, &rp, &l, &events, aov_samples + (size_t)PS_U(ps, job) * AW_AOV_FLOATS);
    if (events & AW_ACC_BAD) atomic_inc(&stats[AW_STAT_BAD_SAMPLES]);
    if (events & AW_ACC_MISSING) atomic_inc(&stats[AW_STAT_MISSING_FEATURE]);
    if (q == AW_Q_FREE) {
      uint job = PS_U(ps, job);
      samples[job * 3u + 0u] = l.x;
      samples[job * 3u + 1u] = l.y;
      samples[job * 3u + 2u] = l.z;
      finished = AW_C_FINISHED + (job >= job_start ? 1u : 0u);
    }
  }
  AW_APPEND_COUNTING(q, slot, finished);
}

// Adds a finished batch to the film, one work-item per pixel (integrator/film.h: exact sums,
// so neither the order nor the batch split matters). A pixel takes a sample only when it is the
// next one it lacks: sample_start + film_count[p]. A fresh render always meets that; a resumed
// one (--resume) starts its jobs at the first sample some pixel lacks, and pixels that already
// hold a sample of that pass skip it, so no sample is counted twice.
AW_STAGE_KERNEL_SCALAR(kernel_film_accumulate) {
  uint p = get_global_id(0);
  uint npix = rp.win_w * rp.win_h;
  if (p >= npix) return;
  // The batch's jobs are job_start .. job_start + job_count - 1 of the ring (RenderParams).
  uint i = job_start + (p + npix - (rp.batch_pixel + job_start) % npix) % npix;  // pixel p's first
  uint s = rp.batch_sample + (rp.batch_pixel + i) / npix;  // its sample index
  uint n = film_count[p];
  uint aov_ch = aov_on(&rp) ? aov_film_channels(rp.aov_mask) : 0u;
  for (; i < job_start + rp.job_count; i += npix, ++s) {
    if (s != rp.sample_start + n) continue;  // held already (a resumed film)
    film_add(film + (size_t)p * AW_FILM_WORDS, make_float3(samples[i * 3u + 0u], samples[i * 3u + 1u], samples[i * 3u + 2u]));
    if (aov_ch) film_add_aovs(aov_film + (size_t)p * aov_ch * 2u, aov_samples + (size_t)i * AW_AOV_FLOATS, rp.aov_mask);
    ++n;
  }
  film_count[p] = n;
}
