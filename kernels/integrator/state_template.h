// The path state, declared once (Cycles' state_template.h is the model).
// Expanded into SoA buffers for the wavefront (field-major: field * pool + slot, so neighbouring
// work-items touch neighbouring words) and into plain arrays of one path for the scalar path.
// Every field is 32 bits: F = float, U = uint.
//
// Included without a guard on purpose: define AW_STATE_F / AW_STATE_U, include, undefine.

/* The ray the path will trace next (extension ray). */
AW_STATE_F(ray_ox) AW_STATE_F(ray_oy) AW_STATE_F(ray_oz)
AW_STATE_F(ray_dx) AW_STATE_F(ray_dy) AW_STATE_F(ray_dz)
/* Path throughput and the radiance gathered so far. */
AW_STATE_F(thr_r) AW_STATE_F(thr_g) AW_STATE_F(thr_b)
/* Product of eta^2 over the interfaces crossed: throughput x eta_scale is what Russian
 * roulette and the cut-off judge, so paths inside glass are not killed for the 1/eta^2
 * that leaving it will undo (pbrt-v4's etaScale). */
AW_STATE_F(eta_scale)
AW_STATE_F(rad_r) AW_STATE_F(rad_g) AW_STATE_F(rad_b)
/* Solid-angle pdf of the last scattering direction (MIS when that ray hits a light). */
AW_STATE_F(bsdf_pdf)
/* Closest hit of the extension ray. */
AW_STATE_F(hit_t) AW_STATE_F(hit_u) AW_STATE_F(hit_v)
/* Shading point written by classify_hit for the lobe stage: position, shading normal and
 * geometric normal, both facing the incoming ray's origin side. */
AW_STATE_F(sp_px) AW_STATE_F(sp_py) AW_STATE_F(sp_pz)
AW_STATE_F(sp_nx) AW_STATE_F(sp_ny) AW_STATE_F(sp_nz)
AW_STATE_F(sp_gx) AW_STATE_F(sp_gy) AW_STATE_F(sp_gz)
/* How far rays leaving the shading point start from it along the geometric normal: the
 * bound on its rounding error (common/ray.h, offset_ray_origin). */
AW_STATE_F(sp_err)
/* Tangent (for anisotropy), orthogonal to the shading normal. */
AW_STATE_F(sp_tx) AW_STATE_F(sp_ty) AW_STATE_F(sp_tz)
/* Textures: the shading point's UV, the path's footprint there in UV units
 * (texture/texture.h), the same in the second UV set, and the shading normal before bump
 * mapping (disable_bump). */
AW_STATE_F(sp_tu) AW_STATE_F(sp_tv) AW_STATE_F(sp_tf)
AW_STATE_F(sp_tu2) AW_STATE_F(sp_tv2) AW_STATE_F(sp_tf2)
AW_STATE_F(sp_bx) AW_STATE_F(sp_by) AW_STATE_F(sp_bz)
/* The path's ray cone (docs/architecture.md#texture-footprint): its width where the current
 * ray starts and its spread angle (radians). */
AW_STATE_F(cone_w) AW_STATE_F(cone_s)
/* The chosen lobe's factor: its energy share divided by the probability of choosing it. */
AW_STATE_F(lobe_wr) AW_STATE_F(lobe_wg) AW_STATE_F(lobe_wb)
/* Factor on light reached through the last scattering (highlight_vs_reflection). */
AW_STATE_F(emit_scale)
/* Shadow ray and what it adds if unoccluded. */
AW_STATE_F(sh_ox) AW_STATE_F(sh_oy) AW_STATE_F(sh_oz)
AW_STATE_F(sh_dx) AW_STATE_F(sh_dy) AW_STATE_F(sh_dz)
AW_STATE_F(sh_tmax)
AW_STATE_F(sh_r) AW_STATE_F(sh_g) AW_STATE_F(sh_b)

AW_STATE_U(job)       /* the job's index in the batch ring: where the result goes */
AW_STATE_U(pixel)
AW_STATE_U(sample)
AW_STATE_U(bounce)    /* scattering events so far = index of the vertex being shaded */
AW_STATE_U(flags)     /* AW_PATH_* */
AW_STATE_U(hit_prim)  /* original triangle id, or ~0u */
AW_STATE_U(hit_inst)  /* the instance hit_prim was hit in (types/bvh.h), or ~0u */
AW_STATE_U(hit_light) /* light index, or ~0u */
AW_STATE_U(material)
AW_STATE_U(sh_light)  /* light the shadow ray aims at (it must not occlude itself), or ~0u */
AW_STATE_U(lobe)      /* AW_LID_* chosen by classify_hit */
AW_STATE_U(depths)    /* reflection bounces (low 16 bits), refraction bounces (high 16 bits) */
AW_STATE_U(medium)    /* material whose fog the path is inside, or ~0u */
