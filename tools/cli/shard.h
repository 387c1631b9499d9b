// Which of a manifest's jobs one process renders: job k belongs to shard k mod N. `--shard I/N`, or `--shard auto`
// from the array index a scheduler sets: Slurm job arrays (SLURM_ARRAY_TASK_ID, _MIN, _STEP, _COUNT), Kubernetes
// Indexed Jobs (JOB_COMPLETION_INDEX, with --shard-count) and AWS Batch arrays (AWS_BATCH_JOB_ARRAY_INDEX, with
// --shard-count).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

namespace penumbra::cli {

struct Shard {
  size_t index = 0, count = 1;
  bool owns(size_t job) const { return job % count == index; }
  std::string label() const;  // "2-of-4": the name of its status file
};

using EnvLookup = std::function<const char*(const char*)>;  // std::getenv, or a test's table

// "" (every job), "I/N" or "auto". Throws std::invalid_argument naming the option or the variable for a bad value,
// an index outside 0..N-1, or `auto` without an array index in the environment (or without the count it needs).
Shard parseShard(const std::string& spec, std::optional<size_t> count, const EnvLookup& env);

}  // namespace penumbra::cli
