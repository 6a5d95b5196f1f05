#include "frame_log.h"

#include <algorithm>
#include <map>

namespace demo {

bool openFrameLog(FrameLog& log, const std::string& path, std::string& error) {
  log.file.open(path);
  if (!log.file) {
    error = path + ": cannot write the benchmark CSV";
    return false;
  }
  return true;
}

void writeFrameRow(FrameLog& log, uint32_t frame, double seconds, double cpuMs, double gbufferMs,
                   const gi::FrameStats& stats, const FrameFacts& facts) {
  std::map<std::string, double> passMs;
  for (const gi::PassTiming& p : stats.passes) {
    if (!passMs.count(p.name) && log.rows == 0) log.passColumns.push_back(p.name);
    passMs[p.name] += p.ms;
  }
  if (log.rows == 0) {
    log.file << "frame,seconds,cpu_ms,gbuffer_ms,module_ms,rays,spp";
    for (const std::string& name : log.passColumns) log.file << ',' << name << "_ms";
    log.file << ",other_ms,memory_bytes,hash_capacity,hash_occupied,hash_failed_inserts,history_frames,method,readying"
                ",fence_waits,idle_waits,creations,module_allocations\n";
  }
  // Passes that were not in the first frame (the method changed) go to other_ms.
  double other = 0.0;
  for (const auto& [name, ms] : passMs)
    if (std::find(log.passColumns.begin(), log.passColumns.end(), name) == log.passColumns.end()) other += ms;
  log.file << frame << ',' << seconds << ',' << cpuMs << ',' << gbufferMs << ',' << stats.totalMs << ','
           << stats.raysTraced << ',' << stats.samplesPerPixel;
  for (const std::string& name : log.passColumns) log.file << ',' << (passMs.count(name) ? passMs[name] : 0.0);
  log.file << ',' << other << ',' << stats.memoryBytes << ',' << stats.hash.capacity << ',' << stats.hash.occupied
           << ',' << stats.hash.failedInserts << ',' << stats.accumulatedFrames << ',' << facts.method << ','
           << (facts.readying ? 1 : 0) << ',' << facts.calls.fenceWaits << ',' << facts.calls.idleWaits << ','
           << facts.calls.creations << ',' << stats.deviceAllocations << '\n';
  log.file.flush();
  ++log.rows;
}

}  // namespace demo
