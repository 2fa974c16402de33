#pragma once
// A sweep as a Slurm job array (docs/sweeps.md): `starnav sweep slurm DIR` writes
// DIR/slurm/sweep.sbatch, whose array job i runs tasks [i * S, (i + 1) * S) of the manifest with
// `starnav sweep run DIR --group i --group-size S`. S is chosen so the array's indices stay below
// the cluster's MaxArraySize (read with `scontrol show config`, Slurm's default 1001 when that is
// not available): a million tasks become 1000 array jobs of 1000 tasks. Only groups with tasks
// left to do are in the array, so submitting again after a partial run redoes nothing finished.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "starnav/sweep/manifest.hpp"

namespace starnav::sweep {

inline constexpr std::uint64_t kSlurmDefaultMaxArraySize = 1001;

// MaxArraySize from the text of `scontrol show config`; nullopt when it is not there.
std::optional<std::uint64_t> parse_max_array_size(std::string_view scontrol_config);

struct ArrayLimit {
  std::uint64_t max_array_size = kSlurmDefaultMaxArraySize;
  std::string source;  // where the value came from, for the script's comment and messages
};
// Asks `scontrol show config`; Slurm's default when scontrol is missing or says nothing.
ArrayLimit query_max_array_size();

// Tasks per array job: at least `tasks_per_job` (0: 1), and enough that the array's indices
// 0 .. groups - 1 stay below `max_array_size`.
std::uint64_t slurm_group_size(std::uint64_t tasks, std::uint64_t max_array_size, std::uint64_t tasks_per_job);

// "0-4,7,9-12" from sorted indices, with "%K" when at most `max_running` may run at once (0: no limit).
std::string slurm_array_spec(const std::vector<std::uint64_t>& indices, std::uint64_t max_running);

struct SlurmOptions {
  std::string partition;
  std::string time;                    // Slurm's forms: MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM, D-HH:MM:SS
  unsigned cpus_per_task = 0;          // 0: not given (one task at a time per array job)
  std::uint64_t tasks_per_job = 0;     // 0: as few as the array-size limit allows
  std::uint64_t max_array_size = 0;    // 0: ask scontrol
  std::uint64_t max_running = 0;       // at most this many array jobs at once (0: no limit)
  std::vector<std::string> sbatch;     // more #SBATCH options, NAME or NAME=VALUE (mem=4G, account=lab)
  std::string starnav;                 // the starnav program on the cluster's nodes (absolute)
  bool retry_failed = false;           // run failed tasks again too
};

struct SlurmScript {
  std::string path;  // DIR/slurm/sweep.sbatch; empty when nothing is left to run
  std::string text;
  ArrayLimit limit;
  std::uint64_t tasks = 0, pending = 0;  // in the manifest; without a record (or failed, with retry_failed)
  std::uint64_t group_size = 0, groups = 0;
  std::vector<std::uint64_t> array;  // the array indices submitted
  std::string array_spec;
};

// Writes the batch script; Error for bad options (naming the flag).
SlurmScript write_slurm_script(const SweepDir& sweep, const SlurmOptions& options);

// Submits with `sbatch --parsable` and returns the job id; Error when sbatch is missing or fails.
std::string submit_slurm_script(const SweepDir& sweep, const SlurmScript& script);

}  // namespace starnav::sweep
