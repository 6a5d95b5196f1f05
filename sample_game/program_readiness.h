// The demo's method switch, which never freezes the window: the chosen
// settings' programs are readied on a thread of the demo's while the old
// method goes on rendering, and the switch is made once they are ready.
//  - gi::preparePrograms creates their pipelines (where the driver compiles
//    at creation, that is the compile).
//  - Where the driver compiles at a program's first dispatch instead (Mesa's
//    lavapipe, whose one queue runs the frames), the programs are dispatched,
//    empty, on a second device (engine/second_device.h) by a stand-in module
//    with the real scene's facts and G-buffer: the driver's on-disk shader
//    cache then holds them, and the first dispatch on the demo's device reads
//    them from it instead of compiling. Without that cache
//    (MESA_SHADER_CACHE_DISABLE) the first frame after the switch compiles.
#pragma once
#include <atomic>
#include <string>
#include <thread>

#include "context.h"
#include "gi/gi.h"

namespace demo {

struct ProgramReadiness {
  std::thread worker;
  std::atomic<bool> finished{false};
  bool busy = false;     // a worker runs (or finished and was not collected yet)
  gi::Settings target;   // what it readies
  std::string error;     // the worker's, if a step failed (the switch then compiles in the frame)
  double seconds = 0.0;  // how long readying took
};

// Whether a driver compiles programs at their first dispatch (lavapipe).
bool compilesAtFirstDispatch(const engine::Context& ctx);
// Starts readying `target` for `module` (made from `desc`); r must not be busy.
void startReadying(ProgramReadiness& r, const engine::Context& ctx, gi::Module* module, const gi::ModuleDesc& desc,
                   const gi::Settings& target);
// True once the worker has finished (then joined: r.target may be applied).
bool collectReady(ProgramReadiness& r);
// Waits for a running worker (at exit).
void joinReadying(ProgramReadiness& r);

}  // namespace demo
