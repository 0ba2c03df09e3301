// Scene features the kernels can be specialised for (docs/design.md, principle 4: model only
// what a scene requires). The list below is the one definition: the feature ids, their bits,
// the compile-time switches and the host's names (host/render/features.h) are all generated
// from it. The host decides the set from the scene (decide_features, host/render/features.cpp)
// and builds the OpenCL program with -DAW_FEATURES=<mask>; without it (the host scalar path,
// the tests, --generic-kernels) every feature is on: the generic build.
//
// Code tests a feature as a constant inside ordinary code, `if (AW_FEAT_X && ...)`, so both
// builds type-check every path and the compiler drops the dead ones in a specialised build.
// AW_FEAT_X is an enumerator, not a macro, so it cannot be used in #if: there is no
// preprocessor splicing of code paths.
//
// Adding a feature: one entry in the material or scene list, its test where material_features()
// (kernels/material/architectural.h) or decide_features() decides it, and `AW_FEAT_X &&` in
// the code path it guards (docs/architecture.md, "How to add a feature").
#ifndef AW_COMMON_FEATURES_H
#define AW_COMMON_FEATURES_H

#include "common/compat.h"

// Material features: what material_features() reports per material, checked at every hit.
#define AW_MATERIAL_FEATURE_LIST(X)                                                            \
  X(TRANSLUCENCY)      /* the translucency lobe carries energy somewhere */                    \
  X(REFLECTION)        /* either reflection lobe carries energy somewhere */                   \
  X(REFRACTION)        /* the refraction lobe carries energy somewhere */                      \
  X(ROUGH_DIFFUSE)     /* some diffuse roughness > 0 (EON instead of Lambert) */               \
  X(ANISOTROPY)        /* an anisotropic reflection */                                         \
  X(FOG)               /* a refractive material with fog */                                    \
  X(CUTOUT)            /* cutout opacity < 0.5 somewhere */                                    \
  X(INCANDESCENCE)     /* an emissive surface */                                               \
  X(BRDF_BECKMANN)     /* a used reflection lobe with brdf "beckmann" */                       \
  X(BRDF_AS)           /* ... "ashikhmin_shirley" or "ashikhmin_shirley_legacy" */             \
  X(FRESNEL_CONDUCTOR) /* ... fresnel.medium "conductor" (with use_ior) */                     \
  X(FRESNEL_CURVE)     /* ... fresnel.use_ior false (facing/perpendicular/curve) */            \
  X(THIN_WALLED)       /* refraction.thin_walled on a material that reflects or transmits */ \
  X(AO)                /* ambient occlusion enabled (integrator/ambient_occlusion.h) */          \
  X(TEXTURE)           /* an input bound to a texture (texture/material_textures.h) */          \
  X(BUMP)              /* a bump map (texture/material_textures.h, bump_normal) */

// Scene features: light types, lobe splitting and the sampler, decided from the scene as a whole.
// The Owen-scrambled Sobol' sampler (the default, and zsobol's continuation past its block) is
// always built; the other two only when render.sampler names them. The switch on a run-time
// value cost PoCL's renders 5-21% (its diffuse stage 16%; Intel's runtime level): measured in
// docs/performance.md, "The sampler, built in".
#define AW_SCENE_FEATURE_LIST(X) \
  X(LIGHT_POINT) X(LIGHT_QUAD) X(LIGHT_DISK) X(LIGHT_SPHERE) \
  X(LIGHT_SUN) /* a sun light (lights/lights.h) */ \
  X(ENV_MAP) /* environment "map" or "sky": an importance-sampled lat-long map (lights/environment.h) */ \
  X(LIGHT_MESH) /* triangles of light-sampled incandescent objects (AW_LIGHT_TRIANGLE) */ \
  X(LIGHT_TREE) /* many lights: the light tree chooses and finds them (lights/light_tree.h) */ \
  X(SPHERE) /* analytic spheres in the BVH (bvh/intersect_sphere.h) */ \
  X(INSTANCE) /* instances of shared meshes: a two-level BVH (bvh/traverse.h) */ \
  X(SPLIT) /* per-lobe samples split rays at the first hit (integrator/split.h) */ \
  X(SAMPLER_INDEPENDENT) X(SAMPLER_ZSOBOL) /* render.sampler (common/rng.h) */ \
  X(AOV) /* arbitrary output variables, render.aovs (integrator/aov.h) */

#define AW_FEATURE_LIST(X) AW_MATERIAL_FEATURE_LIST(X) AW_SCENE_FEATURE_LIST(X)

// Ids in list order (material features first) and the number of each kind.
enum {
#define AW_FEATURE_ID(n) AW_FID_##n,
  AW_FEATURE_LIST(AW_FEATURE_ID)
#undef AW_FEATURE_ID
  AW_FEATURE_COUNT
};
enum {
#define AW_FEATURE_MATERIAL_ID(n) AW_FMID_##n,
  AW_MATERIAL_FEATURE_LIST(AW_FEATURE_MATERIAL_ID)
#undef AW_FEATURE_MATERIAL_ID
  AW_FEAT_MATERIAL_COUNT
};

// One bit per feature: AW_FEATBIT_X = 1 << AW_FID_X.
enum {
#define AW_FEATURE_BIT(n) AW_FEATBIT_##n = 1 << AW_FID_##n,
  AW_FEATURE_LIST(AW_FEATURE_BIT)
#undef AW_FEATURE_BIT
  AW_FEATBIT_ALWAYS = 0  // what a lobe that every build has names as its feature (material/lobes.h)
};

#ifndef AW_FEATURES
#define AW_FEATURES 0xffffffffu  // the generic build: every feature
#endif

// The switches: AW_FEAT_X is 1 when this build has feature X.
enum {
#define AW_FEATURE_SWITCH(n) AW_FEAT_##n = (int)(((uint)(AW_FEATURES) >> AW_FID_##n) & 1u),
  AW_FEATURE_LIST(AW_FEATURE_SWITCH)
#undef AW_FEATURE_SWITCH
  AW_FEAT_ALWAYS = 1
};

// The material features this build has, as AW_FEATBIT_* bits.
#define AW_FEAT_COMPILED_MATERIAL_MASK ((uint)(AW_FEATURES) & ((1u << AW_FEAT_MATERIAL_COUNT) - 1u))

// Always built, not features: the diffuse lobe (Lambert), GGX (the default brdf, and the
// microfacet distribution of rough refraction and frosted thin walls) and the dielectric
// Fresnel (refraction's own): every scene that reflects or refracts at all needs them.

#endif
