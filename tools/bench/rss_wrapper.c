/* hg-bench-rss: runs a command and writes its peak RSS (kB) and wall time (ms) to a file.
   Why a separate tiny program: Linux carries the parent's high-water RSS into a forked child's ru_maxrss
   (exec keeps the larger of the old and new peaks), so hg-bench, which holds the clouds, cannot fork the
   measured process itself; this wrapper is small when it forks.
   usage: hg-bench-rss OUTFILE COMMAND [ARGS...]   (OUTFILE gets "maxrss_kb wall_ms exit_status") */
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <errno.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

int main(int argc, char** argv) {
  static const char usage[] =
      "usage: hg-bench-rss OUTFILE COMMAND [ARGS...]\n"
      "Runs COMMAND (a path) and writes \"maxrss_kb wall_ms exit_status\" to OUTFILE (hg-bench's memory figures).\n";
  if (argc == 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) return fputs(usage, stdout), 0;
  if (argc == 2 && !strcmp(argv[1], "--version")) return printf("hg-bench-rss %s\n", HG_VERSION), 0;
  if (argc < 3) {  /* one line (the failure contract of every program, docs/RUNNING.md) */
    if (argc == 2 && argv[1][0] == '-')
      fprintf(stderr, "hg-bench-rss: command line: unknown option %s (see --help)\n", argv[1]);
    else
      fprintf(stderr, "hg-bench-rss: command line: give OUTFILE COMMAND [ARGS...] (see --help)\n");
    return 2;
  }
  struct timespec t0, t1;
  clock_gettime(CLOCK_MONOTONIC, &t0);
  const pid_t pid = fork();
  if (pid < 0) {
    fprintf(stderr, "hg-bench-rss: fork: %s\n", strerror(errno));
    return 1;
  }
  if (pid == 0) {
    const int devnull = open("/dev/null", O_WRONLY);
    if (devnull >= 0) dup2(devnull, 1);
    execv(argv[2], argv + 2);
    fprintf(stderr, "hg-bench-rss: cannot run %s: %s\n", argv[2], strerror(errno));
    _exit(127);
  }
  int status = 0;
  struct rusage ru;
  memset(&ru, 0, sizeof ru);
  if (wait4(pid, &status, 0, &ru) < 0) {
    fprintf(stderr, "hg-bench-rss: wait4: %s\n", strerror(errno));
    return 1;
  }
  clock_gettime(CLOCK_MONOTONIC, &t1);
  const double ms = (t1.tv_sec - t0.tv_sec) * 1e3 + (t1.tv_nsec - t0.tv_nsec) / 1e6;
  FILE* f = fopen(argv[1], "w");
  if (!f) {
    fprintf(stderr, "hg-bench-rss: cannot write %s: %s\n", argv[1], strerror(errno));
    return 1;
  }
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  fprintf(f, "%ld %.3f %d\n", ru.ru_maxrss, ms, code);
  fclose(f);
  return code;
}
