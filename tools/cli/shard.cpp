// Shards from the command line or the scheduler's environment. Without --shard-count, Slurm's index is made 0-based
// with SLURM_ARRAY_TASK_MIN and _STEP, so `--array=1-8` and `--array=0-14:2` shard like `--array=0-7`; with it, the
// task id is the shard index (a resubmission of chosen indices runs those shards).
#include "tools/cli/shard.h"

#include <fmt/format.h>

#include <charconv>
#include <stdexcept>
#include <string_view>

namespace penumbra::cli {
namespace {

size_t parseCount(std::string_view what, std::string_view text) {
  size_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size())
    throw std::invalid_argument(fmt::format("{}: '{}' is not a whole number", what, text));
  return value;
}

size_t envNumber(const EnvLookup& env, const char* name, std::optional<size_t> fallback = std::nullopt) {
  const char* text = env(name);
  if (text == nullptr) {
    if (fallback) return *fallback;
    throw std::invalid_argument(fmt::format("--shard auto: {} is not set", name));
  }
  return parseCount(name, text);
}

Shard fromEnvironment(std::optional<size_t> count, const EnvLookup& env) {
  if (env("SLURM_ARRAY_TASK_ID") != nullptr) {
    const size_t id = envNumber(env, "SLURM_ARRAY_TASK_ID");
    // With --shard-count N the task id is the shard index itself, so a resubmission of chosen indices
    // (`--array=1,3` of an array 0-3) runs exactly those shards.
    if (count) return {id, *count};
    const size_t min = envNumber(env, "SLURM_ARRAY_TASK_MIN", 0), step = envNumber(env, "SLURM_ARRAY_TASK_STEP", 1);
    if (id < min || step == 0 || (id - min) % step != 0)
      throw std::invalid_argument(fmt::format(
          "--shard auto: SLURM_ARRAY_TASK_ID {} is not on the array MIN {} + k * STEP {} (resubmitting chosen "
          "indices of an earlier array? give --shard-count N, its size: the task id is then the shard index)",
          id, min, step));
    const Shard shard{(id - min) / step, envNumber(env, "SLURM_ARRAY_TASK_COUNT")};
    if (shard.index >= shard.count)
      throw std::invalid_argument(fmt::format(
          "--shard auto: SLURM_ARRAY_TASK_ID {} is shard {} of this array's {} tasks (resubmitting chosen indices of "
          "an earlier array? give --shard-count N, its size: the task id is then the shard index)",
          id, shard.index, shard.count));
    return shard;
  }
  for (const char* name : {"JOB_COMPLETION_INDEX", "AWS_BATCH_JOB_ARRAY_INDEX"}) {
    if (env(name) == nullptr) continue;
    if (!count) throw std::invalid_argument(fmt::format("--shard auto: {} needs --shard-count N", name));
    return {envNumber(env, name), *count};
  }
  throw std::invalid_argument(
      "--shard auto: no array index in the environment (SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX or "
      "AWS_BATCH_JOB_ARRAY_INDEX); use --shard I/N");
}

}  // namespace

std::string Shard::label() const { return fmt::format("{}-of-{}", index, count); }

Shard parseShard(const std::string& spec, std::optional<size_t> count, const EnvLookup& env) {
  Shard shard;
  if (spec.empty()) {
    if (count) throw std::invalid_argument("--shard-count needs --shard auto");
    return shard;
  }
  if (spec == "auto") {
    shard = fromEnvironment(count, env);
  } else {
    const size_t slash = spec.find('/');
    if (slash == std::string::npos) throw std::invalid_argument(fmt::format("--shard {}: use I/N or auto", spec));
    shard = {parseCount("--shard", std::string_view(spec).substr(0, slash)),
             parseCount("--shard", std::string_view(spec).substr(slash + 1))};
    if (count && *count != shard.count)
      throw std::invalid_argument(fmt::format("--shard-count {} contradicts --shard {}", *count, spec));
  }
  if (shard.count == 0) throw std::invalid_argument("--shard: the shard count N must be at least 1");
  if (shard.index >= shard.count)
    throw std::invalid_argument(
        fmt::format("--shard: index {} is not in 0..{} (N = {})", shard.index, shard.count - 1, shard.count));
  return shard;
}

}  // namespace penumbra::cli
