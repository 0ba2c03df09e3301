// The Architectural material as the kernels read it, packed by host/render/scene_pack.cpp
// from host/scene/material_desc.h (docs/material.md). Plain 4-byte fields only (tests/types).
#ifndef AW_TYPES_MATERIAL_H
#define AW_TYPES_MATERIAL_H

// Lobe ids (AW_LID_*) are generated from the lobe list: kernels/material/lobe_list.h.

// Material flags.
#define AW_MAT_METAL 1u
#define AW_MAT_THIN_WALLED 2u
#define AW_MAT_FOG_END_COLOR 4u
#define AW_MAT_HIGHLIGHTS_ONLY 8u
#define AW_MAT_SKIP_WEAK_INTERNAL 16u
#define AW_MAT_TRANSLUCENCY 32u
#define AW_MAT_ANISO_UV_SET1 64u  // anisotropy.uv_set 1: the "uv" frame follows the second UV set

// Ambient occlusion flags (MaterialGpu.ao_flags; docs/material.md §4).
#define AW_AO_MULTIPLY 1u        // combine "multiply" (else "add")
#define AW_AO_INVERT 2u          // invert_normal
#define AW_AO_INCANDESCENCE 4u   // apply_to_incandescence (multiply mode)

// anisotropy.orientation: the frame's tangent from the mesh tangents (interpolated per
// vertex) or from the triangle's UV parametrisation (dP/du). kernels/integrator/classify_hit.h
#define AW_ANISO_TANGENT 0u
#define AW_ANISO_UV 1u

// reflection.brdf (kernels/lobes/reflection.h)
#define AW_BRDF_BECKMANN 0u
#define AW_BRDF_GGX 1u
#define AW_BRDF_ASHIKHMIN_SHIRLEY 2u
#define AW_BRDF_ASHIKHMIN_SHIRLEY_LEGACY 3u

// Fresnel modes (kernels/lobes/fresnel.h)
#define AW_FRESNEL_DIELECTRIC 0u
#define AW_FRESNEL_CONDUCTOR 1u
#define AW_FRESNEL_CURVE 2u
#define AW_FRESNEL_THIN_DIELECTRIC 3u  // a thin pane: both faces' reflections (thin_walled.h)

// One reflection lobe (reflection and reflection2 share the layout). 64 bytes.
typedef struct {
  float color[3];
  float weight;
  float glossiness;
  uint brdf;          // AW_BRDF_* (above)
  uint fresnel_mode;  // AW_FRESNEL_* (above)
  float fresnel_ior;  // resolved: refraction.ior when locked
  float fresnel_k;
  float facing;
  float perpendicular;
  float curve;
  uint samples;
  float cutoff;  // throughput threshold below which this lobe's rays stop; 0 = off
  float pad[2];
} ReflectionGpu;

typedef struct {
  float diffuse_color[3];  // diffuse.color; its weight is diffuse_weight (every lobe keeps its own)
  float diffuse_roughness;
  float transl_color[3];
  float transl_weight;  // 0 unless translucency is enabled
  ReflectionGpu refl[2];
  float refr_color[3];
  float refr_weight;
  float refr_glossiness;
  float refr_ior;
  uint refr_samples;
  float refr_cutoff;
  float fog_end_color[3];
  float fog_distance;  // 0 = no fog
  float incandescent[3];  // colour × scale
  float cutout_opacity;
  float aniso_amount;
  float aniso_rotation;  // 0..1 = 0..360 degrees
  uint aniso_orientation;  // AW_ANISO_TANGENT or AW_ANISO_UV
  float highlight_vs_reflection;
  uint flags;  // AW_MAT_*
  uint refl_depth;  // per-material trace depths (the global ones unless overridden)
  uint refr_depth;
  float diffuse_weight;
  // Ambient occlusion (integrator/ambient_occlusion.h); ao_samples 0 = off.
  float ao_shadow_color[3];
  float ao_max_distance;  // 0 = unlimited
  float ao_ambient_color[3];
  float ao_spread;        // cone half-angle = spread * pi / 2
  float ao_falloff;
  uint ao_samples;
  uint ao_flags;          // AW_AO_*
  float ao_add_scale;     // add mode: 1, or 1 / the exposure scale with exposure_compensation
  // Textures (kernels/texture/material_textures.h): the inputs bound to textures are the
  // bindings [tex_first, tex_first + tex_count) of the scene's binding array; each writes its
  // value over this material's constant in the material the stages read at a hit.
  uint tex_first;
  uint tex_count;
  uint cutout_binding;  // the binding of cutout_opacity (read by the traversal), or AW_NONE
  uint bump_binding;    // bump.input's binding (the height, in scene units per unit value), or AW_NONE
  float bump_scale;     // bump.scale
  uint no_bump_lobes;   // bit AW_LID_x set: lobe x shades with the unbumped normal (disable_bump)
  // material_features() of this material as packed (material/architectural.h), set by the host
  // once the table is final (pack_scene): what a lane program's feature guard reads per hit.
  uint features;
  uint tex_pad;
} MaterialGpu;

#endif
