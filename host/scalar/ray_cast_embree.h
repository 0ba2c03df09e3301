// The scalar path's ray caster: the hook of kernels/integrator/ray_cast.h over Embree's
// rtcIntersect1 / rtcOccluded1.
#pragma once

#include "host/bvh/flat_bvh.h"
#include "kernels/integrator/scene_ref.h"

struct HostRayCaster {
  const aw::EmbreeScene* scene;
};
