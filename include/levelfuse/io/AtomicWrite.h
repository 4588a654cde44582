// levelfuse: output files that appear whole or not at all, alone or as a set.
#pragma once

#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace levelfuse::io {

/// Produces a file at a temporary path; throws if anything went wrong. A
/// writer flushes and checks its stream (a full disk shows there) before it
/// returns: OutputSet then makes the file durable (fsync) before it counts.
using FileWriter = std::function<void(const std::string& temporaryPath)>;

/// The outputs of one run, committed together: each is written to a temporary
/// beside its target, flushed, checked and synced; only when every one has
/// succeeded does commit() rename them over their targets (and sync their
/// folders). If a write throws, or the set is destroyed uncommitted, every
/// temporary is removed and no target is touched. Errors are
/// std::runtime_error naming the target ("cannot write '<path>': ...").
class OutputSet {
 public:
  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  /// Removes the temporaries of a set that was not committed.
  ~OutputSet();

  /// Writes `path`'s content to its temporary now. Refuses a target that
  /// exists and is not a regular file (a folder, a device such as /dev/null),
  /// and a target the set holds already.
  void add(const std::string& path, const FileWriter& write);
  /// Renames every temporary over its target, in the order added, and syncs
  /// the folders. Each rename is atomic; a rename fails only if a folder
  /// changes under the run, and then the targets not yet renamed keep their
  /// old content.
  void commit();
  /// Removes the temporaries; nothing is written.
  void discard();

  /// The targets, in the order added.
  std::vector<std::string> targets() const;

 private:
  struct Entry {
    std::string target, temporary;
  };
  std::vector<Entry> mEntries;
};

/// Closes a writer's stream and throws std::runtime_error if any write, the
/// flush or the close failed (a full disk, an I/O error).
void closeChecked(std::ofstream& out);

/// One file written whole or not at all: an OutputSet of one.
void writeAtomically(const std::string& path, const FileWriter& write);

/// Throws std::runtime_error naming `path` unless a file can be created there
/// (its folder exists and is writable, and nothing but a regular file is at
/// the name): checked before long work.
void requireWritable(const std::string& path);

}  // namespace levelfuse::io
