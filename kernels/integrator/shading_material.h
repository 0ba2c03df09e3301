// The material the stages read at the path's shading point: the scene's own, or, when some of
// its inputs are textured, a copy in the path's slot of mat_resolved with those inputs read at
// the point's UV and footprint (the stages that read the material, classify_hit, the lobe
// stages and ambient occlusion, each apply them again: the copy is the slot's own, and lobe
// splitting returns a slot to its first hit after deeper hits have overwritten it).
#ifndef AW_INTEGRATOR_SHADING_MATERIAL_H
#define AW_INTEGRATOR_SHADING_MATERIAL_H

#include "common/features.h"
#include "integrator/path_state.h"
#include "integrator/scene_ref.h"
#include "material/architectural.h"
#include "texture/material_textures.h"

#if AW_LANES == 1
// The shading point's coordinates in both UV sets (classify_hit, classify_texture_point).
AW_FN SurfaceUv ps_surface_uv(PathRef ps) {
  SurfaceUv s;
  s.u = PS_F(ps, sp_tu);
  s.v = PS_F(ps, sp_tv);
  s.f = PS_F(ps, sp_tf);
  s.u2 = PS_F(ps, sp_tu2);
  s.v2 = PS_F(ps, sp_tv2);
  s.f2 = PS_F(ps, sp_tf2);
  return s;
}

AW_FN MatL shading_material(PathRef ps, SceneRef sc, const RenderParams* rp) {
  (void)rp;
  const AW_GLOBAL MaterialGpu* m = &sc.materials[PS_U(ps, material)];
  if (!(AW_FEAT_TEXTURE && m->tex_count > 0u)) return m;
  AW_GLOBAL MaterialGpu* r = &sc.mat_resolved[ps.slot];
  material_apply_textures(r, m, scene_texture_ref(sc), ps_surface_uv(ps));
  return r;
}
#else
// On lanes: each lane's material in the scene's table. Textures are applied one path per call
// (texture/), so a program built on lanes is built only for scenes without them. A lane that
// is not the stage's path reads material 0: its slot's index may be stale or AW_NONE, and a
// gather through it would read outside the table.
AW_FN MatL shading_material(PathRef ps, SceneRef sc, const RenderParams* rp) {
  MatL m;
  m.table = sc.materials;
  m.n = rp->num_materials;
  m.i = L_SEL(PS_LIVE(ps), PS_LU(ps, material), (luint)(0u));
  return m;
}
#endif

// The normal lobe `lid` shades with: the bumped shading normal, or the one before bump mapping
// where the lobe has disable_bump (docs/material.md §1).
AW_FN lfloat3 shading_normal_for_lobe(PathRef ps, MatL m, uint lid) {
  if (AW_FEAT_BUMP) {
    lmask unbumped = MAT_U(m, bump_binding) != AW_NONE && ((MAT_U(m, no_bump_lobes) >> lid) & 1u) != 0u;
    if (L_ALL(unbumped)) return ps_sp_unbumped_normal(ps);
    if (L_ANY(unbumped)) return l3_sel(unbumped, ps_sp_unbumped_normal(ps), ps_sp_normal(ps));
  }
  return ps_sp_normal(ps);
}

#endif
