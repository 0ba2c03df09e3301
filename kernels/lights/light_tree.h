// Many lights: a light BVH for next-event estimation (Conty Estevez & Kulla 2018, "Importance
// Sampling of Many Lights with Adaptive Tree Splitting", Proc. ACM CGIT 1(2); Sec. 4.1 the
// node's bounds: box, power and orientation cone (axis, theta_o the spread of the emitters'
// normals, theta_e the emission's spread around each normal); Sec. 5.1 the importance of a
// node seen from a point), and the same tree's boxes to find the analytic lights a ray hits.
//
// Selection: from the root, a child is chosen in proportion to its importance at the shading
// point p, and the probability of the light reached is the product of the choices (the tree is
// traversed stochastically, one light per sample; the paper's adaptive splitting, which
// samples several lights where the tree is unsure, is not done). MIS needs that probability
// for a light found by a BSDF ray: light_tree_pmf walks the light's own path from the root
// (its tree_bits, one bit per level, and tree_depth) with the same importances, so both sides
// read the same number. Importance (the paper's Eq. 3 without the receiver's normal, as in
// PBR 4th ed.'s LightBounds::Importance without it, so that reflection and transmission see the
// same pmf): phi cos(theta') / d^2, where theta' = max(0, theta_w - theta_o - theta_b) is the
// smallest angle between the cone of emitter normals and the direction to p (theta_w: from
// the cone's axis to p; theta_b: the half-angle the node's bounding sphere subtends), zero
// when theta' >= theta_e; d^2 is at least the squared half-diagonal of the box, so a point
// inside or beside a node does not make it infinitely important.
//
// Lights at infinity are not in the tree: the host chooses between them (their alias table)
// and the tree with probabilities in proportion to power (RenderParams.tree_prob).
#ifndef AW_LIGHTS_LIGHT_TREE_H
#define AW_LIGHTS_LIGHT_TREE_H

#include "common/compat.h"
#include "common/features.h"
#include "bvh/traverse.h"
#include "lights/lights.h"
#include "types/scene.h"

// Importance of node `nd` seen from p (the paper's Sec. 5.1, in cosines: no acos).
AW_FN float light_node_importance(const AW_GLOBAL LightTreeNode* nd, float3 p) {
  float3 lo = load_f3(nd->bmin), hi = load_f3(nd->bmax);
  float3 c = 0.5f * (lo + hi);
  float3 half_diag = 0.5f * (hi - lo);
  float r2 = dot(half_diag, half_diag);
  float3 pc = p - c;
  float dist2 = dot(pc, pc);
  float d2 = fmax(dist2, r2);
  if (!(d2 > 0.0f)) d2 = 1e-20f;
  float cos_p = 1.0f;  // cos theta'
  if (nd->cos_o > -1.0f && dist2 > r2) {
    // theta_w: from the cone's axis to the direction from the node to p.
    float cos_w = dot(load_f3(nd->axis), pc) / sqrt(dist2);
    cos_w = clamp(cos_w, -1.0f, 1.0f);
    float sin_w = safe_sqrt(1.0f - cos_w * cos_w);
    // theta_x = max(0, theta_w - theta_o).
    float cos_o = nd->cos_o, sin_o = safe_sqrt(1.0f - cos_o * cos_o);
    float cos_x = 1.0f, sin_x = 0.0f;
    if (cos_w < cos_o) {
      cos_x = cos_w * cos_o + sin_w * sin_o;
      sin_x = sin_w * cos_o - cos_w * sin_o;
    }
    // theta' = max(0, theta_x - theta_b), sin theta_b = r / dist.
    float sin_b2 = r2 / dist2;
    float cos_b = safe_sqrt(1.0f - sin_b2), sin_b = sqrt(sin_b2);
    if (cos_x < cos_b) cos_p = cos_x * cos_b + sin_x * sin_b;
    if (cos_p <= nd->cos_e) return 0.0f;
  }
  return nd->power * fmax(cos_p, 0.0f) / d2;
}

// Probability of descending into the first child at inner node i; *second = its second child.
AW_FN float light_tree_left_prob(const AW_GLOBAL LightTreeNode* tree, uint i, float3 p, uint* second) {
  *second = tree[i].child;
  float il = light_node_importance(&tree[i + 1u], p);
  float ir = light_node_importance(&tree[*second], p);
  return il + ir > 0.0f ? il / (il + ir) : -1.0f;  // -1: neither child can light p
}

// Chooses a light of the tree for point p with one uniform number; returns its index in the
// light array (the leaf's `child`) and the probability in *pmf, or AW_NONE (pmf 0) when no
// light can reach p.
AW_FN uint light_tree_sample(const AW_GLOBAL LightTreeNode* tree, float3 p, float u, float* pmf) {
  uint i = 0u;
  float prob = 1.0f;
  while (!tree[i].leaf) {
    uint second;
    float pl = light_tree_left_prob(tree, i, p, &second);
    if (pl < 0.0f) {
      *pmf = 0.0f;
      return AW_NONE;
    }
    if (u < pl) {
      u = u / pl;
      prob *= pl;
      i = i + 1u;
    } else {
      u = (u - pl) / (1.0f - pl);
      prob *= 1.0f - pl;
      i = second;
    }
    u = fmin(u, 0.99999994f);
  }
  *pmf = prob;
  return tree[i].child;
}

// The probability light_tree_sample gives light `l` at p: its path from the root.
AW_FN float light_tree_pmf(const AW_GLOBAL LightTreeNode* tree, const AW_GLOBAL LightGpu* l, float3 p) {
  uint i = 0u;
  float prob = 1.0f;
  for (uint level = 0u; level < l->tree_depth; ++level) {
    uint second;
    float pl = light_tree_left_prob(tree, i, p, &second);
    if (pl < 0.0f) return 0.0f;
    if ((l->tree_bits >> level) & 1u) {
      prob *= 1.0f - pl;
      i = second;
    } else {
      prob *= pl;
      i = i + 1u;
    }
  }
  return prob;
}

// Slab test of a ray against a node's box within (t_min, t_max) (Kay & Kajiya 1986).
AW_FN int light_node_hit(const AW_GLOBAL LightTreeNode* nd, float3 o, float3 inv_d, float t_min, float t_max) {
  float3 t0 = (load_f3(nd->bmin) - o) * inv_d, t1 = (load_f3(nd->bmax) - o) * inv_d;
  float3 lo = fmin(t0, t1), hi = fmax(t0, t1);
  float tn = fmax(fmax(lo.x, lo.y), fmax(lo.z, t_min));
  float tf = fmin(fmin(hi.x, hi.y), fmin(hi.z, t_max));
  return tn <= tf;
}

#define AW_LIGHT_TREE_STACK 64

#if AW_LANES == 1  // (a lane program is built only for scenes without the tree)
// lights_intersect (lights.h) through the tree's boxes: the same answer, the closest light
// along the ray (skipping `skip`, and invisible lights for camera rays), for a scene whose
// many lights would make the loop over all of them the cost of every ray.
AW_FN int light_tree_intersect(const AW_GLOBAL LightTreeNode* tree, const AW_GLOBAL LightGpu* lights, float3 org,
                               float3 dir, float t_min, float* t, int camera_ray, int skip) {
  // safe_rcp (bvh/traverse.h): a zero direction component gives a huge finite reciprocal, so a
  // ray starting on a box's plane computes 0 x 1e30 = 0, never 0 x inf = NaN, which the host's
  // and the device's fmin would treat differently.
  float3 inv_d = make_float3(safe_rcp(dir.x), safe_rcp(dir.y), safe_rcp(dir.z));
  uint stack[AW_LIGHT_TREE_STACK];
  uint sp = 0u;
  uint i = 0u;
  int found = -1;
  for (;;) {
    const AW_GLOBAL LightTreeNode* nd = &tree[i];
    if (light_node_hit(nd, org, inv_d, t_min, *t)) {
      if (!nd->leaf) {
        if (sp < AW_LIGHT_TREE_STACK) stack[sp++] = nd->child;
        i = i + 1u;
        continue;
      }
      uint li = nd->child;
      const AW_GLOBAL LightGpu* l = &lights[li];
      if ((int)li != skip && !(camera_ray && !(l->flags & AW_LIGHT_VISIBLE))) {
        float th = light_intersect(l, org, dir, t_min, *t);
        if (th > 0.0f) {
          *t = th;
          found = (int)li;
        }
      }
    }
    if (sp == 0u) break;
    i = stack[--sp];
  }
  return found;
}

#endif

#endif
