#pragma once

namespace trav::common {

/// The closed range [min, max] a numeric config key (each component of a vector key) must lie in,
/// in the key's unit.
struct Bounds {
  double min;
  double max;
};

// Config structs carry their keys beside their fields, as Drake's Serialize visitors do: one
//
//   template <typename Archive>
//   void Serialize(Archive* a) {
//     a->Field("rate", &points_per_second, {1, 1e6});   // a numeric key needs its Bounds
//     a->Field("table", &pattern_table);                  // flags, text and seeds need none
//     a->Enum("kernel", &kernel);                         // an enum with a common::EnumNames table
//     a->Map("gp", &gp);                                  // a nested struct with its own Serialize
//   }
//
// per struct, with keys relative to the struct. An Archive (the scenario loader's reader, its
// writer of the resolved file, the collectors of the documented keys and bounds) decides what a
// visit does; a struct never knows where it sits in a file. Archives also offer
// Map(key, visit) for a map whose keys come from several structs and
// Sequence(key, &items, max_items, visit) for lists.

}  // namespace trav::common
