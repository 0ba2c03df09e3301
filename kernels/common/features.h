// Scene features the kernels can be specialised for (DESIGN.md principle 4: model only what
// a scene requires). host/render/features.cpp derives the set from the loaded scene and
// builds the OpenCL program with -DAW_SPECIALISED and one -DAW_FEAT_*=0/1 per feature; code
// paths for absent features compile out and their queues are never launched.
// Without AW_SPECIALISED (the host scalar path, the tests, --generic-kernels) every feature
// is on: the generic build.
#ifndef AW_COMMON_FEATURES_H
#define AW_COMMON_FEATURES_H

#ifndef AW_SPECIALISED
#define AW_FEAT_TRANSLUCENCY 1
#define AW_FEAT_REFLECTION 1     // either reflection lobe has weight somewhere
#define AW_FEAT_REFRACTION 1
#define AW_FEAT_ROUGH_DIFFUSE 1  // some diffuse roughness > 0 (EON instead of Lambert)
#define AW_FEAT_ANISOTROPY 1
#define AW_FEAT_FOG 1
#define AW_FEAT_CUTOUT 1
#define AW_FEAT_INCANDESCENCE 1
#define AW_FEAT_BRDF_BECKMANN 1     // a used reflection lobe with brdf "beckmann"
#define AW_FEAT_BRDF_AS 1           // ... "ashikhmin_shirley" or "ashikhmin_shirley_legacy"
#define AW_FEAT_FRESNEL_CONDUCTOR 1 // ... fresnel.medium "conductor" (with use_ior)
#define AW_FEAT_FRESNEL_CURVE 1     // ... fresnel.use_ior false (facing/perpendicular/curve)
#define AW_FEAT_THIN_WALLED 1       // refraction.thin_walled on a material that reflects or transmits
#define AW_FEAT_LIGHT_POINT 1
#define AW_FEAT_LIGHT_QUAD 1
#define AW_FEAT_LIGHT_DISK 1
#define AW_FEAT_LIGHT_SPHERE 1
#define AW_FEAT_SPLIT 1  // per-lobe samples split rays at the first hit (integrator/split.h)
#endif

// Always built, not features: the diffuse lobe (Lambert), GGX (the default brdf, and the
// microfacet distribution of rough refraction and frosted thin walls) and the dielectric
// Fresnel (refraction's own): every scene that reflects or refracts at all needs them.

// One bit per material feature, in list order: material_features()
// (kernels/material/architectural.h) reports what a material uses in these bits, for the
// host's derivation and the kernels' check.
#define AW_FEATBIT_TRANSLUCENCY (1u << 0)
#define AW_FEATBIT_REFLECTION (1u << 1)
#define AW_FEATBIT_REFRACTION (1u << 2)
#define AW_FEATBIT_ROUGH_DIFFUSE (1u << 3)
#define AW_FEATBIT_ANISOTROPY (1u << 4)
#define AW_FEATBIT_FOG (1u << 5)
#define AW_FEATBIT_CUTOUT (1u << 6)
#define AW_FEATBIT_INCANDESCENCE (1u << 7)
#define AW_FEATBIT_BRDF_BECKMANN (1u << 8)
#define AW_FEATBIT_BRDF_AS (1u << 9)
#define AW_FEATBIT_FRESNEL_CONDUCTOR (1u << 10)
#define AW_FEATBIT_FRESNEL_CURVE (1u << 11)
#define AW_FEATBIT_THIN_WALLED (1u << 12)
#define AW_FEAT_MATERIAL_COUNT 13  // the material features come first in AW_FEATURE_LIST
#define AW_FEAT_COMPILED_MATERIAL_MASK                                                           \
  ((AW_FEAT_TRANSLUCENCY ? AW_FEATBIT_TRANSLUCENCY : 0u) | (AW_FEAT_REFLECTION ? AW_FEATBIT_REFLECTION : 0u) | \
   (AW_FEAT_REFRACTION ? AW_FEATBIT_REFRACTION : 0u) | (AW_FEAT_ROUGH_DIFFUSE ? AW_FEATBIT_ROUGH_DIFFUSE : 0u) | \
   (AW_FEAT_ANISOTROPY ? AW_FEATBIT_ANISOTROPY : 0u) | (AW_FEAT_FOG ? AW_FEATBIT_FOG : 0u) |            \
   (AW_FEAT_CUTOUT ? AW_FEATBIT_CUTOUT : 0u) | (AW_FEAT_INCANDESCENCE ? AW_FEATBIT_INCANDESCENCE : 0u) |     \
   (AW_FEAT_BRDF_BECKMANN ? AW_FEATBIT_BRDF_BECKMANN : 0u) | (AW_FEAT_BRDF_AS ? AW_FEATBIT_BRDF_AS : 0u) |   \
   (AW_FEAT_FRESNEL_CONDUCTOR ? AW_FEATBIT_FRESNEL_CONDUCTOR : 0u) |                                        \
   (AW_FEAT_FRESNEL_CURVE ? AW_FEATBIT_FRESNEL_CURVE : 0u) | (AW_FEAT_THIN_WALLED ? AW_FEATBIT_THIN_WALLED : 0u))

// The list, for the host (names in the order of the defines above).
#define AW_FEATURE_LIST(X)                                                                     \
  X(TRANSLUCENCY) X(REFLECTION) X(REFRACTION) X(ROUGH_DIFFUSE) X(ANISOTROPY) X(FOG) X(CUTOUT) \
  X(INCANDESCENCE) X(BRDF_BECKMANN) X(BRDF_AS) X(FRESNEL_CONDUCTOR) X(FRESNEL_CURVE) X(THIN_WALLED)    \
  X(LIGHT_POINT) X(LIGHT_QUAD) X(LIGHT_DISK) X(LIGHT_SPHERE) X(SPLIT)

#endif
