// levelfuse: the records of a .vdb file around its trees (strings, metadata,
// transforms), checked as OpenVDB 10 reads them.
#pragma once

#include "VdbByteReader.h"

#include <string>

namespace levelfuse::io::detail {

/// A string (openvdb::readString): a uint32 length, then the bytes.
std::string readVdbString(VdbByteReader& reader, const char* what);

/// A metadata map (openvdb::MetaMap::readMeta): each item's size must be the
/// size of its type, and variable-size items must fit what they declare.
/// Returns whether it says the grid's values are saved as half floats
/// (openvdb::GridBase::saveFloatAsHalf reads that from the metadata, not
/// from the grid's descriptor).
bool skipVdbMetadata(VdbByteReader& reader, const char* what);

/// A grid's transform (openvdb::math::Transform::read): one of OpenVDB's
/// linear maps, with finite numbers.
void skipVdbTransform(VdbByteReader& reader);

}  // namespace levelfuse::io::detail
