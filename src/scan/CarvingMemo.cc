// levelfuse: space carving's votes kept from one linear solution to the next.

#include <levelfuse/scan/CarvingMemo.h>

#include "CarvingVotes.h"

namespace levelfuse {

CarvingMemo::CarvingMemo() : mRecords(std::make_unique<detail::CarvingRecords>()) {}
CarvingMemo::~CarvingMemo() = default;
CarvingMemo::CarvingMemo(CarvingMemo&&) noexcept = default;
CarvingMemo& CarvingMemo::operator=(CarvingMemo&&) noexcept = default;

void CarvingMemo::clear() {
  const std::lock_guard<std::mutex> answering(mRecords->answering);
  mRecords->clear();
}

std::size_t CarvingMemo::memoryBytes() const {
  const std::lock_guard<std::mutex> answering(mRecords->answering);
  return mRecords->memoryBytes();
}

}  // namespace levelfuse
