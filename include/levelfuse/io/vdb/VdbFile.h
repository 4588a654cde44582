// levelfuse: reading and writing .vdb files.
#pragma once

#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/io/AtomicWrite.h>

#include <openvdb/openvdb.h>

#include <string>

namespace levelfuse::io {

/// Writes `grids` to `path` atomically: into a temporary file beside it, then
/// renamed over it. On any error the temporary is removed, an existing file at
/// `path` is left untouched, and std::runtime_error names the file. The file's
/// UUID is derived from its content: the same grids give the same bytes.
void writeVdb(const std::string& path, const openvdb::GridCPtrVec& grids,
              const openvdb::MetaMap& fileMetadata = openvdb::MetaMap());
/// The same, as one of a run's outputs: committed with the others (AtomicWrite.h).
void writeVdb(OutputSet& outputs, const std::string& path, const openvdb::GridCPtrVec& grids,
              const openvdb::MetaMap& fileMetadata = openvdb::MetaMap());

/// Reads every grid of a .vdb file; InputError names the file and the
/// problem, also for grids that would need more memory than `budget` allows
/// (checked before OpenVDB reads them).
openvdb::GridPtrVecPtr readVdb(const std::string& path, openvdb::MetaMap::Ptr* fileMetadata = nullptr,
                               const MemoryBudget& budget = {});

}  // namespace levelfuse::io
