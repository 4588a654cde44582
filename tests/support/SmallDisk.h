// A full disk for tests: a small tmpfs mounted in a scratch folder and filled.
#pragma once

#include <filesystem>
#include <string>

namespace levelfuse::test {

/// Mounts a tmpfs of `bytes` in a fresh folder (which needs root, or a user
/// namespace that allows it) and unmounts it on destruction. mounted() says
/// whether that worked, reason() why not: tests then skip.
class SmallDisk {
 public:
  explicit SmallDisk(std::size_t bytes = 256 * 1024);
  ~SmallDisk();
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;

  bool mounted() const { return mMounted; }
  const std::string& reason() const { return mReason; }
  std::string path(const std::string& name) const { return (mRoot / name).string(); }
  /// Fills the disk with a file named "filler" until a write fails.
  void fill() const;
  /// How many files the disk holds.
  std::size_t fileCount() const;

 private:
  std::filesystem::path mRoot;
  bool mMounted = false;
  std::string mReason;
};

}  // namespace levelfuse::test
