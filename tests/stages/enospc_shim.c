/* Test-only LD_PRELOAD shim (tests/stages/disk_full_test.cc, used where no size-limited file
 * system can be mounted): a disk that holds HAPSTATE_ENOSPC_BYTES bytes written to the files
 * directly in the directory HAPSTATE_ENOSPC_DIR (an absolute path, no trailing '/'). A write
 * that would go beyond fails with ENOSPC (or the errno number HAPSTATE_ENOSPC_ERRNO, e.g. 5 for
 * EIO), and so does every later one there: the disk stays full. Other files are untouched.
 * Intercepts what HDF5's sec2 driver and SQLite's unix VFS write with: write, pwrite, pwrite64,
 * writev, pwritev. Never built into a shipped program. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static pthread_mutex_t shim_mutex = PTHREAD_MUTEX_INITIALIZER;
static long long shim_written = 0;
static int shim_full = 0;

/* Whether `fd` is a file directly in HAPSTATE_ENOSPC_DIR. */
static int shim_watched(int fd) {
  const char* dir = getenv("HAPSTATE_ENOSPC_DIR");
  if (dir == NULL || dir[0] == '\0') return 0;
  char link[64], path[PATH_MAX];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const int saved = errno;
  const ssize_t n = readlink(link, path, sizeof path - 1);
  errno = saved;
  if (n <= 0) return 0;
  path[n] = '\0';
  const size_t len = strlen(dir);
  return strncmp(path, dir, len) == 0 && path[len] == '/' && strchr(path + len + 1, '/') == NULL;
}

/* 0 if `count` more bytes fit on the watched disk (and counts them), else -1 with ENOSPC. */
static int shim_charge(int fd, size_t count) {
  if (count == 0 || !shim_watched(fd)) return 0;
  const char* bytes = getenv("HAPSTATE_ENOSPC_BYTES");
  const long long limit = bytes != NULL ? atoll(bytes) : 0;
  int ok;
  pthread_mutex_lock(&shim_mutex);
  ok = !shim_full && shim_written + (long long)count <= limit;
  if (ok)
    shim_written += (long long)count;
  else
    shim_full = 1;
  pthread_mutex_unlock(&shim_mutex);
  if (ok) return 0;
  const char* error = getenv("HAPSTATE_ENOSPC_ERRNO");
  errno = error != NULL && atoi(error) > 0 ? atoi(error) : ENOSPC;
  return -1;
}

static size_t shim_iov_bytes(const struct iovec* iov, int n) {
  size_t total = 0;
  for (int k = 0; k < n; ++k) total += iov[k].iov_len;
  return total;
}

typedef ssize_t (*write_fn)(int, const void*, size_t);
typedef ssize_t (*pwrite_fn)(int, const void*, size_t, off_t);
typedef ssize_t (*pwrite64_fn)(int, const void*, size_t, off64_t);
typedef ssize_t (*writev_fn)(int, const struct iovec*, int);
typedef ssize_t (*pwritev_fn)(int, const struct iovec*, int, off_t);

#define SHIM_REAL(name, type) \
  static type real = NULL;    \
  if (real == NULL) real = (type)dlsym(RTLD_NEXT, name)

ssize_t write(int fd, const void* buf, size_t count) {
  SHIM_REAL("write", write_fn);
  if (shim_charge(fd, count) != 0) return -1;
  return real(fd, buf, count);
}

ssize_t pwrite(int fd, const void* buf, size_t count, off_t offset) {
  SHIM_REAL("pwrite", pwrite_fn);
  if (shim_charge(fd, count) != 0) return -1;
  return real(fd, buf, count, offset);
}

ssize_t pwrite64(int fd, const void* buf, size_t count, off64_t offset) {
  SHIM_REAL("pwrite64", pwrite64_fn);
  if (shim_charge(fd, count) != 0) return -1;
  return real(fd, buf, count, offset);
}

ssize_t writev(int fd, const struct iovec* iov, int n) {
  SHIM_REAL("writev", writev_fn);
  if (shim_charge(fd, shim_iov_bytes(iov, n)) != 0) return -1;
  return real(fd, iov, n);
}

ssize_t pwritev(int fd, const struct iovec* iov, int n, off_t offset) {
  SHIM_REAL("pwritev", pwritev_fn);
  if (shim_charge(fd, shim_iov_bytes(iov, n)) != 0) return -1;
  return real(fd, iov, n, offset);
}
