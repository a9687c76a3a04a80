#pragma once
/// Joining partial bakes of one scene (`bake --quads A-B`) into the lookup a
/// whole bake would have written: pure table logic; reading the parts and
/// refusing foreign ones with file names is io/lookup_io's merge_lookups.

#include <string>
#include <vector>

#include "core/bake/lookup_table.h"

namespace clothbake {

/// The first layout field in which two tables of one K differ ("gutter",
/// "sizes", "sides.front.size", ...; empty if none): parts of one bake share
/// everything but their flags and texels.
std::string layout_mismatch(const LookupTable& a, const LookupTable& b);

/// `merged` (the first part's layout) becomes the union of `parts` (each a
/// list of tables, one per object, all of merged's layout): every flag baked
/// in any part, every baked square (with its gutter) copied from the first
/// part that baked it. Byte for byte what a whole bake writes.
void merge_tables(std::vector<LookupTable>& merged,
                  const std::vector<std::vector<LookupTable>>& parts);

}  // namespace clothbake
