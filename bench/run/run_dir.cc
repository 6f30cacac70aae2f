#include "bench/run/run_dir.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "bench/run/csv.h"
#include "bench/run/runner.h"
#include "bench/run/schema.h"
#include "bench/run/summary.h"
#include "bench/run/table.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPartial = "run.partial";
// The streamed files, in the order a task's blocks are appended (tasks.idx comes after them): the
// first six in every run, rig.csv too in a rig run (RunConfig::HasRig; NumStreamed).
constexpr int kFiles = 7;
constexpr const char* kStreamed[kFiles] = {"runs.csv",   "timings.csv", "curves.csv",
                                           "events.csv", "tracks.csv",  "track_errors.csv",
                                           "rig.csv"};
int NumStreamed(bool rig) { return rig ? kFiles : kFiles - 1; }

// One finished task in tasks.idx: the end offsets of its blocks in the streamed files.
struct IndexEntry {
  long task = -1;
  long end[kFiles] = {0, 0, 0, 0, 0, 0, 0};
};

std::string IndexHeader(const ShardSpec& shard, long total) {
  return "# calibench tasks: shard " + shard.ToString() + " of " + std::to_string(total) + "\n";
}

std::string IndexLine(const IndexEntry& e, int files) {
  std::string line = std::to_string(e.task);
  for (int f = 0; f < files; ++f) line += " " + std::to_string(e.end[f]);
  return line + "\n";
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Reads tasks.idx: its header line and the complete entries (a cut last line is ignored).
// *bytes_valid is the length of the part that parsed.
bool ReadIndex(const std::string& path, int files, std::string* header,
               std::vector<IndexEntry>* entries, long* bytes_valid, std::string* why) {
  const std::string text = Slurp(path);
  const size_t eol = text.find('\n');
  if (eol == std::string::npos) {
    *why = path + ": no header line (not a calibench tasks.idx)";
    return false;
  }
  *header = text.substr(0, eol + 1);
  entries->clear();
  size_t pos = eol + 1;
  while (pos < text.size()) {
    const size_t end = text.find('\n', pos);
    if (end == std::string::npos) break;  // Cut short by a kill: not a finished task.
    IndexEntry e;
    std::istringstream line(text.substr(pos, end - pos));
    line >> e.task;
    for (int f = 0; f < files; ++f) line >> e.end[f];
    if (!line) {
      *why = path + ": line " + std::to_string(entries->size() + 2) + ": malformed entry";
      return false;
    }
    entries->push_back(e);
    pos = end + 1;
  }
  *bytes_valid = static_cast<long>(pos);
  return true;
}

std::string Errno(const std::string& path, const std::string& what) {
  return path + ": " + what + ": " + std::strerror(errno);
}

// Appends whole task blocks to the streamed files and tasks.idx, tracking the offsets.
class PartialWriter {
 public:
  ~PartialWriter() { Close(); }

  bool Open(const std::string& dir, const IndexEntry& last, int files, std::string* why) {
    dir_ = dir;
    last_ = last;
    files_count_ = files;
    for (int f = 0; f <= files; ++f) {
      const std::string path = dir + "/" + (f < files ? kStreamed[f] : "tasks.idx");
      files_[f] = std::fopen(path.c_str(), "ab");
      if (files_[f] == nullptr) {
        *why = Errno(path, "cannot open for appending");
        return false;
      }
    }
    return true;
  }

  bool Append(long task, const std::string (&blocks)[kFiles], std::string* why) {
    IndexEntry entry;
    entry.task = task;
    for (int f = 0; f < files_count_; ++f) {
      if (!Write(f, blocks[f], why)) return false;
      entry.end[f] = last_.end[f] + static_cast<long>(blocks[f].size());
    }
    if (!Write(files_count_, IndexLine(entry, files_count_), why)) return false;
    last_ = entry;
    return true;
  }

  bool Close() {
    bool ok = true;
    for (FILE*& f : files_) {
      if (f != nullptr) ok = std::fclose(f) == 0 && ok;
      f = nullptr;
    }
    return ok;
  }

 private:
  bool Write(int f, const std::string& text, std::string* why) {
    if (text.empty()) return true;
    if (std::fwrite(text.data(), 1, text.size(), files_[f]) != text.size() ||
        std::fflush(files_[f]) != 0) {
      *why = Errno(dir_ + "/" + (f < files_count_ ? kStreamed[f] : "tasks.idx"), "write failed");
      return false;
    }
    return true;
  }

  std::string dir_;
  IndexEntry last_;
  int files_count_ = kFiles - 1;
  FILE* files_[kFiles + 1] = {};
};

std::string HeaderBlock(int file, bool rig) {
  const std::vector<std::string>* headers[kFiles] = {
      &RunRowHeader(), &TimingHeader(),     &CurveHeader(), &EventHeader(),
      &TrackHeader(),  &TrackErrorHeader(), &RigHeader()};
  return CsvLine(file == kFiles - 1 ? *headers[file] : WithCameraColumn(*headers[file], rig));
}

// Creates run.partial with the three headers and tasks.idx's header and -1 entry (*headers).
bool CreatePartial(const std::string& partial, const std::string& index_header, bool rig,
                   IndexEntry* headers, std::string* why) {
  std::error_code ec;
  fs::remove_all(partial, ec);
  fs::create_directories(partial, ec);
  if (ec) {
    *why = partial + ": cannot create: " + ec.message();
    return false;
  }
  *headers = IndexEntry();
  for (int f = 0; f < NumStreamed(rig); ++f) {
    const std::string block = HeaderBlock(f, rig);
    headers->end[f] = static_cast<long>(block.size());
    if (!WriteFileAtomically(partial + "/" + kStreamed[f], block, why)) return false;
  }
  return WriteFileAtomically(partial + "/tasks.idx",
                             index_header + IndexLine(*headers, NumStreamed(rig)), why);
}

// Cuts the streamed files and tasks.idx back to the last complete task; *last is that entry.
bool TruncatePartial(const std::string& partial, const std::string& index_header, int files,
                     const std::vector<long>& owned, IndexEntry* last, long* resumed,
                     std::string* why) {
  std::string header;
  std::vector<IndexEntry> entries;
  long index_bytes = 0;
  if (!ReadIndex(partial + "/tasks.idx", files, &header, &entries, &index_bytes, why)) return false;
  if (header != index_header) {
    *why = partial + "/tasks.idx: written for '" + header.substr(0, header.size() - 1) +
           "', not '" + index_header.substr(0, index_header.size() - 1) +
           "' (run without --resume to start over)";
    return false;
  }
  if (entries.empty() || entries[0].task != -1) {
    *why = partial + "/tasks.idx: the header entry is missing";
    return false;
  }
  long line_bytes = static_cast<long>(header.size() + IndexLine(entries[0], files).size());
  size_t done = 0;
  for (size_t i = 1; i < entries.size(); ++i) {
    if (done >= owned.size() || entries[i].task != owned[done]) {
      *why = partial + "/tasks.idx: line " + std::to_string(i + 2) + ": task " +
             std::to_string(entries[i].task) + " is out of order";
      return false;
    }
    ++done;
    line_bytes += static_cast<long>(IndexLine(entries[i], files).size());
  }
  *last = entries[done];
  *resumed = static_cast<long>(done);
  for (int f = 0; f < files; ++f) {
    const std::string path = partial + "/" + kStreamed[f];
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec || static_cast<long>(size) < last->end[f]) {
      *why = path + ": shorter than tasks.idx says (" + std::to_string(last->end[f]) +
             " bytes): the directory was changed by hand; run without --resume";
      return false;
    }
    fs::resize_file(path, static_cast<uintmax_t>(last->end[f]), ec);
    if (ec) {
      *why = path + ": cannot truncate: " + ec.message();
      return false;
    }
  }
  std::error_code ec;
  fs::resize_file(partial + "/tasks.idx", static_cast<uintmax_t>(line_bytes), ec);
  if (ec) *why = partial + "/tasks.idx: cannot truncate: " + ec.message();
  return !ec;
}

// summary.csv and table.md from the partial runs.csv, schema.json from the configuration, then
// every file moves into `dir` (tasks.idx last). Idempotent: a finalisation cut short by a kill
// completes on --resume.
bool Finalize(const RunConfig& config, const std::string& dir, std::string* why) {
  const std::string partial = dir + "/" + kPartial;
  if (fs::exists(partial + "/runs.csv")) {
    std::string summary;
    if (!SummarizeRuns(partial + "/runs.csv", &summary, why) ||
        !WriteFileAtomically(partial + "/summary.csv", summary, why)) {
      return false;
    }
    // The thesis table: the reference method's rows of the scenarios that are not sweep points.
    std::map<std::string, std::string> tabled;  // Scenario -> the instance its table shows.
    std::vector<ScenarioConfig> scenarios;
    for (const ScenarioConfig& s : config.scenarios) {
      if (s.sweep_point.measurement_index < 0) {
        tabled.emplace(s.name, ReferenceMethod(s));
        scenarios.push_back(s);
      }
    }
    std::vector<RunRow> rows;
    std::ifstream in(partial + "/runs.csv", std::ios::binary);
    CsvReader reader(&in);
    std::vector<std::string> header, fields;
    reader.Next(&header, why);
    while (!tabled.empty() && reader.Next(&fields, why)) {
      RunRow row;
      if (fields.size() != header.size() || fields[0].empty() || !tabled.count(fields[0])) continue;
      if (!ParseRunRow(header, fields, &row, why)) return false;
      if (row.method == tabled.at(row.scenario)) rows.push_back(std::move(row));
    }
    const std::string table = scenarios.empty() ? "" : ThesisTable(scenarios, rows);
    if (!WriteFileAtomically(partial + "/table.md", table, why)) return false;
    if (!WriteFileAtomically(partial + "/schema.json", SchemaJson(config), why)) return false;
    std::string bands;
    if (!SummarizeTrackErrors(partial + "/track_errors.csv", &bands, why) ||
        !WriteFileAtomically(partial + "/track_bands.csv", bands, why)) {
      return false;
    }
  }
  for (const char* name :
       {"runs.csv", "timings.csv", "curves.csv", "events.csv", "tracks.csv", "track_errors.csv",
        "rig.csv", "summary.csv", "track_bands.csv", "table.md", "schema.json", "tasks.idx"}) {
    const std::string from = partial + "/" + name;
    if (!fs::exists(from)) continue;
    if (std::rename(from.c_str(), (dir + "/" + name).c_str()) != 0) {
      *why = Errno(dir + "/" + name, "cannot move into place");
      return false;
    }
  }
  std::error_code ec;
  fs::remove_all(partial, ec);
  return true;
}

}  // namespace

bool ShardSpec::Parse(const std::string& text, std::string* why) {
  int k = 0, n = 0;
  char slash = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &k, &slash, &n, &extra) != 3 || slash != '/' || n < 1 ||
      k < 1 || k > n) {
    if (why) *why = "--shard: expected K/N with 1 <= K <= N, got '" + text + "'";
    return false;
  }
  index = k;
  count = n;
  return true;
}

namespace {

// This shard's tasks among all of the configuration's, in order, and their indices.
struct ShardTasks {
  std::vector<TrialTask> tasks;
  std::vector<long> owned;
  long total = 0;  // Tasks of the whole sweep.
};
ShardTasks TasksOfShard(const RunConfig& config, const std::vector<std::vector<int>>& groups,
                        const ShardSpec& shard) {
  ShardTasks out;
  const std::vector<TrialTask> all_tasks = ListTasks(config.scenarios, groups);
  out.total = static_cast<long>(all_tasks.size());
  for (const TrialTask& t : all_tasks) {
    if (!shard.Owns(t.index)) continue;
    out.tasks.push_back(t);
    out.owned.push_back(t.index);
  }
  return out;
}

enum class DirectoryState { kFailed, kComplete, kReady };

// Makes `dir` ready to receive rows: a fresh run writes the resolved configuration and an empty
// run.partial; --resume checks that the configuration is the interrupted run's and truncates
// run.partial to its last whole task (summary->tasks_resumed), or finds the run complete.
DirectoryState PrepareDirectory(const std::string& resolved, const std::string& index_header,
                                bool rig, const ShardTasks& shard, const RunDirOptions& options,
                                IndexEntry* last, RunDirSummary* summary, std::string* why) {
  const std::string& dir = options.out_dir;
  const std::string partial = dir + "/" + kPartial;
  const std::string resolved_path = dir + "/config.resolved.yaml";
  if (!options.resume || !(fs::exists(partial + "/tasks.idx") || fs::exists(dir + "/tasks.idx"))) {
    if (!WriteFileAtomically(resolved_path, resolved, why)) return DirectoryState::kFailed;
    if (!CreatePartial(partial, index_header, rig, last, why)) return DirectoryState::kFailed;
    return DirectoryState::kReady;
  }
  if (Slurp(resolved_path) != resolved) {
    *why = resolved_path +
           ": --resume: the configuration differs from the interrupted run's; run without "
           "--resume to start over";
    return DirectoryState::kFailed;
  }
  if (!fs::exists(partial + "/tasks.idx")) {  // Finished before: only check and re-finalise.
    std::string header;
    std::vector<IndexEntry> entries;
    long bytes = 0;
    if (!ReadIndex(dir + "/tasks.idx", NumStreamed(rig), &header, &entries, &bytes, why)) {
      return DirectoryState::kFailed;
    }
    if (header != index_header) {
      *why = dir + "/tasks.idx: another shard's directory";
      return DirectoryState::kFailed;
    }
    summary->tasks_resumed = summary->tasks_total;
    return DirectoryState::kComplete;
  }
  if (fs::exists(partial + "/runs.csv")) {
    if (!TruncatePartial(partial, index_header, NumStreamed(rig), shard.owned, last,
                         &summary->tasks_resumed, why)) {
      return DirectoryState::kFailed;
    }
  } else {
    summary->tasks_resumed = summary->tasks_total;  // Cut short while moving files: finish that.
  }
  return DirectoryState::kReady;
}

// The CSV blocks of one task's rows, one per streamed file (kStreamed).
void TaskBlocks(const std::vector<RunRow>& rows, const std::map<std::string, int>& band_samples,
                bool rig, std::string (&blocks)[kFiles]) {
  for (const RunRow& r : rows) {
    blocks[0] += CsvLine(RunRowFields(r, rig));
    blocks[1] += CsvLine(TimingFields(r, rig));
    blocks[3] += EventLines(r, rig);
    if (r.trial == 0) blocks[4] += TrackLines(r, rig);
    blocks[5] += TrackErrorLines(r, band_samples.at(r.scenario), rig);
    for (const auto& [t, e] : r.curve) {
      std::vector<std::string> fields = {r.scenario, std::to_string(r.trial), r.method,
                                         FormatNumber(t), FormatNumber(e)};
      if (rig) fields.push_back(std::to_string(r.camera));
      blocks[2] += CsvLine(fields);
    }
    if (rig) blocks[6] += RigLines(r);
  }
}

// Runs `remaining` (tasks first.. of the shard) and appends each task's rows to run.partial in
// task order. False (and *error) when a write fails or should_stop interrupts.
bool RunRemaining(const RunConfig& config, const std::vector<std::vector<int>>& groups,
                  const std::vector<TrialTask>& remaining, long first, const IndexEntry& last,
                  const RunDirOptions& options, RunDirSummary* summary, std::string* error) {
  const std::string partial = options.out_dir + "/" + kPartial;
  const bool rig = config.HasRig();
  PartialWriter writer;
  if (!writer.Open(partial, last, NumStreamed(rig), error)) return false;
  TaskRunOptions run_options;
  run_options.threads = options.threads;
  run_options.max_buffered_tasks = options.max_buffered_tasks;
  run_options.curve_trials = options.curve_trials;
  std::map<std::string, int> band_samples;  // Per scenario: tracking.band_samples.
  for (const ScenarioConfig& s : config.scenarios) band_samples[s.name] = s.tracking.band_samples;
  auto commit = [&](size_t position, std::vector<RunRow>&& rows) {
    std::string blocks[kFiles];
    TaskBlocks(rows, band_samples, rig, blocks);
    if (!writer.Append(remaining[position].index, blocks, error)) return false;
    summary->rows_written += static_cast<long>(rows.size());
    ++summary->tasks_run;
    if (options.progress) options.progress(first + summary->tasks_run, summary->tasks_total);
    if (options.should_stop && options.should_stop()) {
      *error = "interrupted after " + std::to_string(summary->tasks_run) +
               " tasks: continue with --resume";
      return false;
    }
    return true;
  };
  RunTasksInOrder(config.scenarios, groups, remaining, run_options, commit);
  if (!writer.Close() && error->empty()) *error = partial + ": closing the files failed";
  return error->empty();
}

}  // namespace

RunDirSummary RunToDirectory(const RunConfig& config, const RunDirOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  RunDirSummary summary;
  auto fail = [&](const std::string& why) {
    summary.ok = false;
    summary.message = why;
    summary.wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  };
  const std::string& dir = options.out_dir;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return fail(dir + ": cannot create the output directory: " + ec.message());

  const std::vector<std::vector<int>> groups = MeasurementGroups(config.scenarios);
  const ShardTasks shard = TasksOfShard(config, groups, options.shard);
  summary.tasks_total = static_cast<long>(shard.tasks.size());
  const std::string index_header = IndexHeader(options.shard, shard.total);
  std::string why;
  IndexEntry last;
  switch (PrepareDirectory(ResolvedYaml(config), index_header, config.HasRig(), shard, options,
                           &last, &summary, &why)) {
    case DirectoryState::kFailed:
      return fail(why);
    case DirectoryState::kComplete:
      summary.ok = true;
      summary.message = "already complete";
      return summary;
    case DirectoryState::kReady:
      break;
  }
  const long first = summary.tasks_resumed;
  if (summary.tasks_total > first) {
    const std::vector<TrialTask> remaining(shard.tasks.begin() + first, shard.tasks.end());
    std::string error;
    if (!RunRemaining(config, groups, remaining, first, last, options, &summary, &error)) {
      return fail(error);
    }
  }
  if (!Finalize(config, dir, &why)) return fail(why);
  summary.ok = true;
  summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

namespace {

// A finished shard's directory and its index; `next` is the next entry to copy.
struct Shard {
  std::string dir;
  std::vector<IndexEntry> entries;
  size_t next = 1;
};

// Reads every shard's index and checks that they are one sweep's: the same resolved
// configuration, finished, each of 1/N..N/N once. *count = N, *total = the sweep's tasks.
bool ReadShards(const std::vector<std::string>& shard_dirs, const std::string& resolved, int files,
                std::map<int, Shard>* shards, int* count, long* total, std::string* why) {
  *count = -1;
  *total = -1;
  for (const std::string& d : shard_dirs) {
    if (fs::exists(d + "/" + kPartial)) {
      *why = d + ": unfinished (run.partial exists): finish it with --resume first";
      return false;
    }
    if (Slurp(d + "/config.resolved.yaml") != resolved) {
      *why = d + "/config.resolved.yaml: differs from " + shard_dirs[0] + "'s: not one sweep";
      return false;
    }
    std::string header;
    Shard shard;
    shard.dir = d;
    long bytes = 0;
    if (!ReadIndex(d + "/tasks.idx", files, &header, &shard.entries, &bytes, why)) return false;
    int k = 0, n = 0;
    long t = 0;
    if (std::sscanf(header.c_str(), "# calibench tasks: shard %d/%d of %ld", &k, &n, &t) != 3 ||
        (*count >= 0 && (n != *count || t != *total)) || shards->count(k)) {
      *why = d + "/tasks.idx: '" + header.substr(0, header.size() - 1) +
             "' does not fit the other shards (each of 1/N..N/N once, one N)";
      return false;
    }
    *count = n;
    *total = t;
    (*shards)[k] = std::move(shard);
  }
  if (static_cast<int>(shards->size()) != *count) {
    *why = "merge: " + std::to_string(shards->size()) + " shard directories given, the sweep has " +
           std::to_string(*count) + " shards";
    return false;
  }
  return true;
}

// Copies task 0..total-1, in order, from the shard that ran it (task t: shard t mod N + 1) to
// `writer`, byte for byte.
bool CopyTasks(std::map<int, Shard>* shards, int count, long total, int files,
               PartialWriter* writer, std::string* why) {
  std::map<int, std::array<std::ifstream, kFiles>> streams;
  for (auto& [k, shard] : *shards) {
    for (int f = 0; f < files; ++f) {
      streams[k][f].open(shard.dir + "/" + kStreamed[f], std::ios::binary);
    }
  }
  for (long task = 0; task < total; ++task) {
    const int k = static_cast<int>(task % count) + 1;
    Shard& shard = (*shards)[k];
    if (shard.next >= shard.entries.size() || shard.entries[shard.next].task != task) {
      *why = shard.dir + "/tasks.idx: task " + std::to_string(task) + " is missing";
      return false;
    }
    const IndexEntry& from = shard.entries[shard.next - 1];
    const IndexEntry& to = shard.entries[shard.next++];
    std::string blocks[kFiles];
    for (int f = 0; f < files; ++f) {
      blocks[f].resize(static_cast<size_t>(to.end[f] - from.end[f]));
      streams[k][f].seekg(from.end[f]);
      if (!streams[k][f].read(blocks[f].data(), static_cast<long>(blocks[f].size()))) {
        *why = shard.dir + "/" + kStreamed[f] + ": shorter than its tasks.idx says";
        return false;
      }
    }
    if (!writer->Append(task, blocks, why)) return false;
  }
  return true;
}

}  // namespace

bool MergeRunDirectories(const std::vector<std::string>& shard_dirs, const std::string& out_dir,
                         std::string* why) {
  if (shard_dirs.empty()) {
    *why = "merge: no shard directories given";
    return false;
  }
  const std::string resolved = Slurp(shard_dirs[0] + "/config.resolved.yaml");
  if (resolved.empty()) {
    *why = shard_dirs[0] + "/config.resolved.yaml: missing or empty";
    return false;
  }
  RunConfig config;
  if (!LoadRunConfig(shard_dirs[0] + "/config.resolved.yaml", &config, why)) return false;
  const bool rig = config.HasRig();
  std::map<int, Shard> shards;
  int count = 0;
  long total = 0;
  if (!ReadShards(shard_dirs, resolved, NumStreamed(rig), &shards, &count, &total, why)) {
    return false;
  }
  const std::string partial = out_dir + "/" + kPartial;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) {
    *why = out_dir + ": cannot create the output directory: " + ec.message();
    return false;
  }
  if (!WriteFileAtomically(out_dir + "/config.resolved.yaml", resolved, why)) return false;
  IndexEntry last;
  if (!CreatePartial(partial, IndexHeader(ShardSpec(), total), rig, &last, why)) return false;
  PartialWriter writer;
  if (!writer.Open(partial, last, NumStreamed(rig), why)) return false;
  if (!CopyTasks(&shards, count, total, NumStreamed(rig), &writer, why)) return false;
  if (!writer.Close()) {
    *why = partial + ": closing the files failed";
    return false;
  }
  return Finalize(config, out_dir, why);
}

}  // namespace calibench
