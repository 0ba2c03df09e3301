// The stages' one argument list, declared once: every stage kernel (integrator/kernels.cl)
// takes exactly these parameters in this order, and the host (host/render/wavefront.cpp)
// binds them by the generated AW_ARG_* indices, never by literal position. Reordering or
// adding an argument here changes both sides at once.
//
//   VALUE(type, name)   passed by value, set per launch
//   BUFFER(type, name)  a __global buffer, bound once per render
// The RenderParams `rp` always comes first (AW_ARG_rp = 0) and is set per launch too.
#ifndef AW_INTEGRATOR_STAGE_ARGS_H
#define AW_INTEGRATOR_STAGE_ARGS_H

#define AW_STAGE_ARGS(VALUE, BUFFER)                                                        \
  VALUE(uint, count)      /* items in the launch: queue entries, or pixels (film) */        \
  VALUE(uint, dense)      /* 1: one work-item per pool slot, in slot order (kernels.cl) */  \
  VALUE(uint, job_start)  /* regenerate: the job of its first item; accumulate: the batch \
                             ring's half size; film_accumulate: its batch's first job */  \
  BUFFER(float, sf)       /* path state, float fields (integrator/state_template.h) */     \
  BUFFER(uint, su)        /* path state, uint fields */                                     \
  BUFFER(uint, queues)    /* queue q at [q * pool, (q + 1) * pool) */                       \
  BUFFER(uint, counters)  /* one entry count per queue, then AW_C_FINISHED (queues.h) */     \
  BUFFER(uint, tags)      /* the queue each slot is in (dense launches) */                  \
  BUFFER(float, snap_f)   /* lobe splitting's first-hit snapshots (integrator/split.h) */   \
  BUFFER(uint, snap_u)                                                                      \
  BUFFER(float, samples)  /* the batch ring's sample values, 3 floats per job */           \
  BUFFER(uint, stats)     /* AW_STAT_* counters (integrator/queues.h) */                    \
  BUFFER(ulong, film)     /* per-pixel exact sums, AW_FILM_WORDS (integrator/film.h) */   \
  BUFFER(uint, film_count)                                                                  \
  BUFFER(float, aov_state)   /* AOVs (integrator/aov.h): per slot, the first hit's data */  \
  BUFFER(float, aov_samples) /* per job, AW_AOV_FLOATS */                                   \
  BUFFER(ulong, aov_film)    /* per pixel, the chosen AOVs' exact sums, 2 words a channel */ \
  BUFFER(float4, nodes)   /* the flattened BVH (kernels/types/bvh.h) */                     \
  BUFFER(float4, tris)                                                                      \
  BUFFER(InstanceGpu, insts) /* instances of shared meshes (types/bvh.h) */                \
  BUFFER(TriangleInfo, tri_info)                                                            \
  BUFFER(VertexData, verts)                                                                 \
  BUFFER(MaterialGpu, materials)                                                            \
  BUFFER(LightGpu, lights)                                                                  \
  BUFFER(float, env)      /* the environment map (lights/environment.h) */                 \
  BUFFER(LightTreeNode, light_tree) /* the light tree (lights/light_tree.h) */             \
  BUFFER(uint, tri_light) /* per triangle its mesh light, or AW_NONE */                    \
  BUFFER(TextureGpu, textures) /* kernels/texture/texture.h */                             \
  BUFFER(TexBindingGpu, tex_bindings) /* material inputs bound to textures */              \
  BUFFER(uchar, texels)   /* every texture's texels, all levels */                          \
  BUFFER(MaterialGpu, mat_resolved) /* per pool slot: the hit's material, textures applied */

enum {
  AW_ARG_rp,
#define AW_STAGE_ARG_INDEX(type, name) AW_ARG_##name,
  AW_STAGE_ARGS(AW_STAGE_ARG_INDEX, AW_STAGE_ARG_INDEX)
#undef AW_STAGE_ARG_INDEX
  AW_ARG_COUNT
};

#endif
