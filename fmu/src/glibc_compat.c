/* The FMU's own definitions of the few glibc symbols newer than 2.28 that
 * the statically linked parts (libstdc++, libgcc's unwinder, libsodium) and
 * our code reference when built on a new system (Debian 12: glibc 2.36).
 *
 * The FMU runs inside someone else's process, on the engineer's machine:
 * RHEL 8, Ubuntu 20.04, Debian 10 have glibc 2.28-2.31. A module that
 * references e.g. arc4random@GLIBC_2.36 does not load there at all ("version
 * `GLIBC_2.36' not found"). Each definition below is linked into the module
 * (hidden: the version script exports only fmi2*, fmi3* and pcs_fmu_*), so the
 * static archives bind to it and the module needs nothing newer than
 * GLIBC_2.28 from libc; fmu.portable_binary_and_packaging checks that with
 * objdump -T.
 *
 * Each one does what glibc's does, with an older interface:
 *   stat, lstat, fstat, fstat64  the system calls (glibc < 2.33 had only
 *                                __xstat; on x86-64 the kernel's struct stat
 *                                is glibc's)
 *   arc4random                   getrandom(2), or /dev/urandom where the
 *                                kernel lacks it; aborts rather than return a
 *                                weak value (libstdc++'s std::random_device
 *                                references it)
 *   _dl_find_object              dl_iterate_phdr: the unwinder asks it for the
 *                                .eh_frame_hdr of the object holding a pc
 *   pthread_once                 one recursive lock for all once-controls
 *                                (it moved from libpthread to libc in 2.34)
 *   __pthread_key_create         referenced only for its address, as libstdc++'s
 *                                "threads may exist" test; never called
 *   __libc_single_threaded       0: libstdc++ then always uses atomic
 *                                reference counts, which is right in any host
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <link.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#if !defined(__x86_64__)
#error "glibc_compat.c: the stat system calls below assume x86-64's struct stat"
#endif

#define PCS_HIDDEN __attribute__((visibility("hidden")))

/* ---- stat family (GLIBC_2.33) ---- */
PCS_HIDDEN int stat(const char* restrict path, struct stat* restrict st) {
  return (int)syscall(SYS_newfstatat, AT_FDCWD, path, st, 0);
}
PCS_HIDDEN int lstat(const char* restrict path, struct stat* restrict st) {
  return (int)syscall(SYS_newfstatat, AT_FDCWD, path, st, AT_SYMLINK_NOFOLLOW);
}
PCS_HIDDEN int fstat(int fd, struct stat* st) { return (int)syscall(SYS_fstat, fd, st); }
PCS_HIDDEN int fstat64(int fd, struct stat64* st) { return (int)syscall(SYS_fstat, fd, st); }

/* ---- arc4random (GLIBC_2.36) ---- */
static int fill_from_urandom(void* buf, size_t n) {
  int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return -1;
  unsigned char* p = (unsigned char*)buf;
  while (n > 0) {
    ssize_t r = read(fd, p, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) {
      close(fd);
      return -1;
    }
    p += r;
    n -= (size_t)r;
  }
  close(fd);
  return 0;
}

static void random_bytes(void* buf, size_t n) {
  unsigned char* p = (unsigned char*)buf;
  size_t left = n;
  while (left > 0) {
    long r = syscall(SYS_getrandom, p, left, 0);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      if (errno == ENOSYS && fill_from_urandom(p, left) == 0) return;  /* kernel before 3.17 */
      abort();                                                          /* no source of randomness */
    }
    p += r;
    left -= (size_t)r;
  }
}

PCS_HIDDEN uint32_t arc4random(void) {
  uint32_t v;
  random_bytes(&v, sizeof v);
  return v;
}

/* ---- _dl_find_object (GLIBC_2.35) ---- */
#ifndef DLFO_STRUCT_HAS_EH_DBASE /* headers before 2.35: its layout as 2.35's <dlfcn.h> gives it */
struct dl_find_object {
  unsigned long long dlfo_flags;
  void* dlfo_map_start;
  void* dlfo_map_end;
  struct link_map* dlfo_link_map;
  void* dlfo_eh_frame;
  unsigned long long dlfo_reserved[7];
};
#endif

struct find_query {
  uintptr_t pc;
  struct dl_find_object* out;
  int found;
};

static int find_in_object(struct dl_phdr_info* info, size_t size, void* data) {
  (void)size;
  struct find_query* q = (struct find_query*)data;
  uintptr_t lo = UINTPTR_MAX, hi = 0;
  int holds_pc = 0;
  void* eh = NULL;
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)* ph = &info->dlpi_phdr[i];
    uintptr_t start = info->dlpi_addr + ph->p_vaddr;
    if (ph->p_type == PT_LOAD) {
      if (start < lo) lo = start;
      if (start + ph->p_memsz > hi) hi = start + ph->p_memsz;
      if (q->pc >= start && q->pc < start + ph->p_memsz) holds_pc = 1;
    } else if (ph->p_type == PT_GNU_EH_FRAME) {
      eh = (void*)start;
    }
  }
  if (!holds_pc) return 0;
  memset(q->out, 0, sizeof *q->out);
  q->out->dlfo_map_start = (void*)lo;
  q->out->dlfo_map_end = (void*)hi;
  q->out->dlfo_eh_frame = eh;
  q->found = 1;
  return 1;
}

PCS_HIDDEN int _dl_find_object(void* pc, struct dl_find_object* result) {
  struct find_query q = {(uintptr_t)pc, result, 0};
  dl_iterate_phdr(find_in_object, &q);
  return q.found ? 0 : -1;
}

/* ---- pthread_once (GLIBC_2.34; libpthread's before) ---- */
static pthread_mutex_t once_lock = PTHREAD_RECURSIVE_MUTEX_INITIALIZER_NP;

/* Runs when pthread_once returns and when an exception from init (std::call_once
 * of a throwing callable) unwinds through it (built with -fexceptions): the
 * control stays 0, so the next call tries again, as POSIX and C++ want. */
static void release_once_lock(pthread_mutex_t** lock) { pthread_mutex_unlock(*lock); }

PCS_HIDDEN int pthread_once(pthread_once_t* control, void (*init)(void)) {
  if (__atomic_load_n(control, __ATOMIC_ACQUIRE) == 1) return 0;
  pthread_mutex_lock(&once_lock);
  pthread_mutex_t* held __attribute__((cleanup(release_once_lock))) = &once_lock;
  if (__atomic_load_n(control, __ATOMIC_RELAXED) == 0) {
    init();  /* an init that calls pthread_once for another control may: the lock is recursive */
    __atomic_store_n(control, 1, __ATOMIC_RELEASE);
  }
  return 0;
}

/* ---- libstdc++'s thread test (GLIBC_2.34 weak reference) ---- */
int __pthread_key_create(pthread_key_t* key, void (*destructor)(void*)) PCS_HIDDEN;
int __pthread_key_create(pthread_key_t* key, void (*destructor)(void*)) {
  (void)key;
  (void)destructor;
  return ENOSYS;
}

/* ---- __libc_single_threaded (GLIBC_2.32) ---- */
PCS_HIDDEN char __libc_single_threaded = 0;
