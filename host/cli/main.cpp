// The fracref command-line tool: parses the command line and maps errors to exit codes.
#include <iostream>
#include <new>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "cli.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace {

// The refiner allocates and frees arrays the size of the surface several times per iteration;
// glibc serves blocks over 128 KiB by mmap and returns them to the kernel on free, so every
// iteration paid again for zeroed pages (page faults on every new array). Freed blocks stay in
// the heap instead; the peak memory is unchanged.
void keep_freed_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory();
  try {
    return fracref::cli::run(argc, argv);
  } catch (const std::bad_alloc&) {
    // The failed allocation's memory was never taken and the unwinding freed the rest, so this
    // message can still be built.
    const std::string what = fracref::cli::activity();
    std::cerr << "fracref: out of memory" << (what.empty() ? "" : " while " + what)
              << " (a smaller field.resolution, refine.max_triangles or input needs less)\n";
    return fracref::kExitFailure;
  } catch (const fracref::InputError& e) {
    std::cerr << "fracref: " << fracref::user_text(e.what()) << "\n";
    return fracref::kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "fracref: " << fracref::user_text(e.what()) << "\n";
    return fracref::kExitFailure;
  }
}
