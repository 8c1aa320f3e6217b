// A scene moved by an offset, all of it (instances, decals, lights, probes and the camera): what
// camera-relative rendering must render as it renders the scene where it was.
#pragma once

#include "passes/scene/scene.h"

namespace nightcap::test {

inline Scene moved(Scene scene, const glm::dvec3& offset) {
  for (Instance& instance : scene.instances) instance.world[3] += glm::dvec4(offset, 0.0);
  for (Decal& decal : scene.decals) decal.world[3] += glm::dvec4(offset, 0.0);
  for (Light& light : scene.lights) {
    light.position += offset;
    light.end += offset;
  }
  for (ReflectionProbe& probe : scene.probes) {
    probe.position += offset;
    probe.box_min += offset;
    probe.box_max += offset;
  }
  if (scene.camera) scene.camera->world[3] += glm::dvec4(offset, 0.0);
  return scene;
}

}  // namespace nightcap::test
