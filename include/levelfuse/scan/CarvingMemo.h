// levelfuse: space carving's votes kept from one linear solution to the next
// while maps keep coming.
#pragma once

#include <cstddef>
#include <memory>

namespace levelfuse {

namespace detail {
struct CarvingRecords;
}

/// Space carving's votes on the voxels and blocks around the data, kept from
/// one linear solution to the next of a sequence of maps that grows between
/// them (a fusion's answers during a scan): the next answer asks the new maps
/// of what was asked before, and every map only of what is new. The votes
/// are sums, so the answer is the one carving from scratch gives, bit for
/// bit. One answer at a time uses a memo; it forgets its votes when the
/// voxel size, the readings' thickness or the sequence changes (fewer maps),
/// and an interrupted answer the votes it had taken out.
class CarvingMemo {
 public:
  CarvingMemo();
  ~CarvingMemo();
  CarvingMemo(CarvingMemo&&) noexcept;
  CarvingMemo& operator=(CarvingMemo&&) noexcept;

  /// Forgets every vote.
  void clear();
  /// Memory held by the votes (bytes).
  std::size_t memoryBytes() const;
  detail::CarvingRecords& records() { return *mRecords; }

 private:
  std::unique_ptr<detail::CarvingRecords> mRecords;
};

}  // namespace levelfuse
