// The material's lobes, listed once. Everything that enumerates lobes is generated from this
// list: the lobe ids, their queues (integrator/queues.h: AW_Q_COUNT), the shading entry
// points (integrator/kernels.cl), the host's kernel names (host/render/wavefront.cpp), which
// build has which lobe (lobe_feature_bit), and the setup/eval/pdf/sample/samples dispatch
// (material/lobes.h).
//
//   X(ID, name, FEATURE, TRAITS)
//     ID       AW_LID_<ID>; its queue is AW_Q_LOBE + AW_LID_<ID>
//     name     the shading kernel shade_<name>, and the binding functions
//              material_<name>_setup/_eval/_pdf/_sample/_samples/_present (material/lobes.h)
//     FEATURE  the feature (common/features.h) a build needs to have this lobe; ALWAYS: every build
//     TRAITS   AW_LT_* below: what the path logic around the lobe (integrator/shade_surface.h)
//              needs to know about it
//
// Order matters only for the energy split's tie-breaking in material_pick_lobe (lobes are
// tried in list order) and for the queue numbering; adding a lobe at the end keeps both.
// How to add one: docs/architecture.md, "How to add a lobe".
#ifndef AW_MATERIAL_LOBE_LIST_H
#define AW_MATERIAL_LOBE_LIST_H

#include "common/features.h"

#define AW_LT_REFLECTION 1u  // a reflection lobe: anisotropic frame, highlight_vs_reflection, reflection depth
#define AW_LT_TRANSMIT 2u    // lights behind the surface: next-event estimation on the far side
#define AW_LT_REFRACTION 4u  // crosses the interface: refraction depth, entering or leaving fog

#define AW_LOBE_ROW_DIFFUSE(X) X(DIFFUSE, diffuse, ALWAYS, 0u)
#define AW_LOBE_LIST(X)                                                         \
  AW_LOBE_ROW_DIFFUSE(X)                                                        \
  X(TRANSLUCENCY, translucency, TRANSLUCENCY, AW_LT_TRANSMIT)                   \
  X(REFLECTION, reflection, REFLECTION, AW_LT_REFLECTION)                       \
  X(REFLECTION2, reflection2, REFLECTION, AW_LT_REFLECTION)                     \
  X(REFRACTION, refraction, REFRACTION, AW_LT_TRANSMIT | AW_LT_REFRACTION)

// The lobes whose physics is written on lanes (common/lanes.h), so far the diffuse lobe: the
// lobe dispatch of a program built with W > 1 lanes (material/lobes.h) has only these, and
// such a program is built only for scenes whose materials use no other.
#define AW_LOBE_LIST_ON_LANES(X) AW_LOBE_ROW_DIFFUSE(X)

enum {
#define AW_LOBE_ID(ID, name, FEATURE, TRAITS) AW_LID_##ID,
  AW_LOBE_LIST(AW_LOBE_ID)
#undef AW_LOBE_ID
  AW_LID_COUNT
};

// The feature bit (AW_FEATBIT_*) a build needs to have lobe `lid`; 0 = every build has it.
AW_FN uint lobe_feature_bit(uint lid) {
#define AW_LOBE_FEATURE(ID, name, FEATURE, TRAITS) \
  if (lid == (uint)AW_LID_##ID) return (uint)AW_FEATBIT_##FEATURE;
  AW_LOBE_LIST(AW_LOBE_FEATURE)
#undef AW_LOBE_FEATURE
  return 0u;
}

// Whether this build has the shading kernel of lobe `lid`.
AW_FN int lobe_compiled(uint lid) { return (lobe_feature_bit(lid) & ~AW_FEAT_COMPILED_MATERIAL_MASK) == 0u; }

// The lobe's AW_LT_* traits.
AW_FN uint lobe_traits(uint lid) {
#define AW_LOBE_TRAITS(ID, name, FEATURE, TRAITS) \
  if (lid == (uint)AW_LID_##ID) return TRAITS;
  AW_LOBE_LIST(AW_LOBE_TRAITS)
#undef AW_LOBE_TRAITS
  return 0u;
}

#endif
