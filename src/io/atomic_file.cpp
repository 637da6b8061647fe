#include <fmt/format.h>
#include <fmt/std.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

namespace msh::io {
namespace fs = std::filesystem;

namespace {
fs::path temp_name(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  return target.parent_path() /
         fmt::format(".{}.tmp-{}-{}", target.filename().string(), ::getpid(), counter++);
}
fs::path directory_of(const fs::path& target) {
  return target.parent_path().empty() ? fs::path(".") : target.parent_path();
}
void check_directory(const fs::path& target) {
  std::error_code ec;
  if (!fs::is_directory(directory_of(target), ec))
    throw InputError(fmt::format("cannot write '{}': no such directory", target.string()));
}

// The temporaries in flight, readable from a signal handler: fixed slots (no allocation), each free (0),
// being filled (1) or holding a NUL-terminated path (2); lock-free atomics only. A temporary that finds no
// free slot (more than kSlots files written at once) is still removed by its destructor and by the next run.
constexpr int kSlots = 256;
constexpr std::size_t kPathBytes = 4096;
struct TempSlot {
  std::atomic<int> state{0};
  char path[kPathBytes];
};
TempSlot g_slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free);

int register_temporary(const fs::path& p) {
  const std::string& s = p.native();
  if (s.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int free_state = 0;
    if (g_slots[i].state.compare_exchange_strong(free_state, 1)) {
      std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
      g_slots[i].state.store(2);
      return i;
    }
  }
  return -1;
}
void release_temporary(int slot) {
  if (slot >= 0) g_slots[slot].state.store(0);
}
extern "C" void remove_temporaries_and_reraise(int sig) {
  for (TempSlot& t : g_slots)
    if (t.state.load() == 2) ::unlink(t.path);
  // SA_RESETHAND restored the default action: the signal ends the process as it would have.
  ::raise(sig);
}

// ".NAME.tmp-PID-N" → PID (0: not a temporary of ours).
long temporary_pid(const std::string& name) {
  if (name.empty() || name[0] != '.') return 0;
  const auto at = name.rfind(".tmp-");
  if (at == std::string::npos || at == 0) return 0;
  const std::string rest = name.substr(at + 5);
  const auto dash = rest.find('-');
  if (dash == std::string::npos || dash == 0 || dash + 1 == rest.size()) return 0;
  const std::string pid = rest.substr(0, dash), n = rest.substr(dash + 1);
  const auto digits = [](const std::string& d) {
    return d.size() <= 18 && std::all_of(d.begin(), d.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(pid) || !digits(n)) return 0;
  return std::stol(pid);
}
// The first write into a directory removes the temporaries there whose process is gone (killed before its
// destructor or handler ran). A live process's (another run writing there) are left alone.
void sweep_stale_temporaries(const fs::path& target) {
  static std::mutex m;
  static std::set<std::string> swept;
  std::error_code ec;
  const fs::path dir = fs::absolute(directory_of(target), ec).lexically_normal();
  if (ec) return;
  const std::lock_guard<std::mutex> lock(m);
  if (!swept.insert(dir.native()).second) return;
  for (fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    const long pid = temporary_pid(it->path().filename().native());
    if (pid <= 0 || pid == long(::getpid())) continue;
    if (::kill(pid_t(pid), 0) == -1 && errno == ESRCH) {
      std::error_code rec;
      if (fs::is_regular_file(it->symlink_status(rec))) fs::remove(it->path(), rec);
    }
  }
}

// The files committed under each live OutputFolder's directory.
struct Recorder {
  fs::path dir;
  std::set<std::string> files;  // relative to dir, generic form
};
std::mutex g_record_mutex;
std::map<std::size_t, Recorder> g_recorders;
std::size_t g_next_recorder = 0;

fs::path absolute_normal(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  return (ec ? p : a).lexically_normal();
}
// p relative to dir when p lies under it ("" otherwise).
std::string relative_under(const fs::path& p, const fs::path& dir) {
  const fs::path rel = p.lexically_relative(dir);
  if (rel.empty() || rel == "." || *rel.begin() == "..") return {};
  return rel.generic_string();
}
void record_commit(const fs::path& target) {
  const std::lock_guard<std::mutex> lock(g_record_mutex);
  if (g_recorders.empty()) return;
  const fs::path a = absolute_normal(target);
  for (auto& [id, r] : g_recorders)
    if (std::string rel = relative_under(a, r.dir); !rel.empty()) r.files.insert(std::move(rel));
}
}  // namespace

void install_temporary_cleanup() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) != 0 || old.sa_handler != SIG_DFL) continue;  // e.g. nohup's SIG_IGN
    struct sigaction sa {};
    sa.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    ::sigaction(sig, &sa, nullptr);
  }
}

AtomicPath::AtomicPath(fs::path target) : target_(std::move(target)) {
  if (target_.filename().empty())
    throw InputError(fmt::format("cannot write '{}': not a file name", target_.string()));
  check_directory(target_);
  // Replacing a device, FIFO or socket by a regular file would be a surprise (`convert x.npy /dev/null`);
  // a symlink is followed for the check and replaced by the rename, as any editor's save does.
  std::error_code ec;
  const fs::file_status st = fs::status(target_, ec);
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw InputError(fmt::format("cannot write '{}': it exists and is not a regular file", target_.string()));
  sweep_stale_temporaries(target_);
  temp_ = temp_name(target_);
  slot_ = register_temporary(temp_);
}

AtomicPath::~AtomicPath() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
  release_temporary(slot_);
}

void AtomicPath::commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw InputError(fmt::format("cannot write '{}': {}", target_.string(), ec.message()));
  committed_ = true;
  release_temporary(slot_), slot_ = -1;
  record_commit(target_);
}

void rename_recorded_directory(const fs::path& from, const fs::path& to) {
  fs::rename(from, to);
  const std::lock_guard<std::mutex> lock(g_record_mutex);
  const fs::path af = absolute_normal(from), at = absolute_normal(to);
  for (auto& [id, r] : g_recorders) {
    const std::string rf = relative_under(af, r.dir), rt = relative_under(at, r.dir);
    if (rf.empty()) continue;
    std::set<std::string> moved;
    for (auto it = r.files.begin(); it != r.files.end();) {
      if (it->size() > rf.size() && it->compare(0, rf.size(), rf) == 0 && (*it)[rf.size()] == '/') {
        if (!rt.empty()) moved.insert(rt + it->substr(rf.size()));
        it = r.files.erase(it);
      } else {
        ++it;
      }
    }
    r.files.insert(moved.begin(), moved.end());
  }
}

void write_file_atomic(const fs::path& path, std::span<const std::byte> bytes) {
  AtomicPath ap(path);
  std::FILE* f = std::fopen(ap.temp().c_str(), "wb");
  if (!f) throw InputError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(errno)));
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && std::fflush(f) == 0;
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) throw InputError(fmt::format("cannot write '{}': write failed", path.string()));
  ap.commit();
}

void write_file_atomic(const fs::path& path, std::string_view text) {
  write_file_atomic(path, std::as_bytes(std::span<const char>(text.data(), text.size())));
}

OutputFolder::OutputFolder(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  const fs::file_status st = fs::status(dir_, ec);
  if (fs::exists(st) && !fs::is_directory(st))
    throw InputError(fmt::format("cannot write into '{}': it exists and is not a directory", dir_.string()));
  const std::lock_guard<std::mutex> lock(g_record_mutex);
  id_ = g_next_recorder++;
  g_recorders[id_].dir = absolute_normal(dir_);
}

OutputFolder::~OutputFolder() {
  const std::lock_guard<std::mutex> lock(g_record_mutex);
  g_recorders.erase(id_);
}

std::vector<std::string> OutputFolder::finish() {
  std::set<std::string> now;
  {
    const std::lock_guard<std::mutex> lock(g_record_mutex);
    now = g_recorders[id_].files;
  }
  now.erase(kManifest);
  std::error_code dir_ec;
  if (!fs::is_directory(dir_, dir_ec)) return {};  // the run wrote nothing (and made no folder)
  // The previous run's list: only relative paths under dir (a hand-edited list cannot reach outside).
  std::set<std::string> before;
  const fs::path manifest = dir_ / kManifest;
  std::error_code ec;
  if (fs::is_regular_file(manifest, ec)) {
    std::ifstream in(manifest);
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      const fs::path rel = fs::path(line).lexically_normal();
      if (rel.is_absolute() || rel.empty() || *rel.begin() == ".." || rel == ".") continue;
      before.insert(rel.generic_string());
    }
  }
  std::ostringstream out;
  out << "# the files microshadow wrote here in its last complete run (removed when a later run does not "
         "write them)\n";
  for (const std::string& f : now) out << f << "\n";
  write_file_atomic(manifest, out.str());
  std::vector<std::string> removed;
  for (const std::string& f : before) {
    if (now.count(f)) continue;
    const fs::path p = dir_ / f;
    std::error_code rec;
    if (!fs::is_regular_file(fs::symlink_status(p, rec))) continue;
    if (!fs::remove(p, rec) || rec) continue;
    removed.push_back(f);
    // The directories it leaves empty, up to dir (exclusive).
    for (fs::path d = fs::path(f).parent_path(); !d.empty(); d = d.parent_path()) {
      std::error_code dec;
      if (!fs::is_empty(dir_ / d, dec) || dec || !fs::remove(dir_ / d, dec)) break;
    }
  }
  return removed;
}

}  // namespace msh::io
