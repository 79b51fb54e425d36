// Switches that make a frame work as the CRSH thesis printed it and trace the rays and objects it
// traced (docs/hierarchy.md, "Faithful to the thesis"): render, diff and bench register them with one
// function, so their defaults agree; the defaults are the frame rayspace traces.
#pragma once
#include <string>
#include <vector>

#include "rayspace/emu/frame.h"
#include "rayspace/reproduce/faithful_presets.h"
#include "rayspace/emu/hierarchy.h"

namespace rayspace::app {

struct FaithfulArgs {
  std::string preset = "none";                           // --faithful none|thesis|roger
  std::string hash_order = "interleaved";                // --hash-order interleaved|polar-first
  int hash_bits = emu::HierarchyConfig{}.hash.polar_bits;  // --hash-bits: shadow keys' cells per angle
  std::string shadow_rule = "all";                       // --shadow-rule all|lit
  std::string shadow_bounces = "all";                    // --shadow-bounces all|first
  bool one_object = false;                               // --one-object
  std::string cone_test = "conservative";                // --cone-test conservative|printed|printed-signed
  std::string leaf_test = "node";                        // --leaf-test node|ray-sphere
  std::string child_merge = "sequential";                // --child-merge sequential|pairwise
};

// The largest --hash-bits: a shadow key holds the light index and both angles' cells.
int MaxHashBits();
// Sets the hierarchy configuration's fields the switches name; --cone-test printed takes --objects
// auto as flat and refuses --objects tree (the object tree's descent has only the conservative test).
void ApplyFaithful(const FaithfulArgs& args, emu::HierarchyConfig& hc);
// The scene's buffers; with --one-object every triangle in one object (one bounding sphere), each
// triangle keeping its material, as the thesis's Sponza was "not divided into submeshes".
SceneBuffers FlattenForFrame(const Scene& scene, const FaithfulArgs& args);
// Sets the frame options the switches name.
void ApplyFaithful(const FaithfulArgs& args, emu::FrameOptions& fo);

}  // namespace rayspace::app
