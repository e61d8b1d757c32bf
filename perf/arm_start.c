/* Start-up of the bare-metal performance driver (perf/perf_step.cpp) when it
 * runs under qemu-arm's user-mode emulator rather than on a board.
 *
 * The code is built for the Cortex-M0 (ARMv6-M Thumb-1, soft float, newlib's
 * v6-m/nofp libraries) but started as a Linux process: qemu-arm 7.2 aborts
 * when asked for an M-profile CPU in user mode, and newlib's semihosting
 * start-up uses BKPT, which user mode does not serve. So: no crt0, this
 * _start runs the static constructors and main, output and exit are Linux
 * system calls (svc 0), and the heap of the double reference's std::vector is
 * a static arena (qemu maps the ELF's segments, nothing beyond `end`).
 * Thumb-1 is a subset of what qemu's `any` CPU executes, so the instructions
 * counted are exactly the Cortex-M0 build's. */
#include <stddef.h>

extern int main(void);
extern void (*__init_array_start[])(void);
extern void (*__init_array_end[])(void);

void* __dso_handle = 0;

void sw_sys_write(const char* s, unsigned n) {
  register int r0 __asm__("r0") = 1;
  register const char* r1 __asm__("r1") = s;
  register unsigned r2 __asm__("r2") = n;
  register int r7 __asm__("r7") = 4; /* write */
  __asm__ volatile("svc 0" : "+r"(r0) : "r"(r1), "r"(r2), "r"(r7) : "memory");
}

__attribute__((noreturn)) static void sw_sys_exit(int code) {
  register int r0 __asm__("r0") = code;
  register int r7 __asm__("r7") = 1; /* exit */
  for (;;) {
    __asm__ volatile("svc 0" : : "r"(r0), "r"(r7));
  }
}

static unsigned char sw_heap[512 * 1024] __attribute__((aligned(8)));
static size_t sw_heap_used;

void* _sbrk(ptrdiff_t incr) {
  if (incr < 0 || (size_t)incr > sizeof sw_heap - sw_heap_used) {
    return (void*)-1;
  }
  void* p = sw_heap + sw_heap_used;
  sw_heap_used += (size_t)incr;
  return p;
}

void _start(void) {
  for (void (**f)(void) = __init_array_start; f != __init_array_end; ++f) {
    (*f)();
  }
  sw_sys_exit(main());
}
