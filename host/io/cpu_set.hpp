#pragma once
// How many CPUs this process may run on: the CPUs of its affinity mask (sched_getaffinity), which
// Slurm's --cpus-per-task, taskset and cgroup cpusets set, not the machine's core count
// (std::thread::hardware_concurrency), which on a big node would overload the task's share.
namespace splatcl {

// The CPUs in the calling thread's affinity mask, at least 1 (hardware_concurrency where the
// system cannot say).
unsigned usable_cpus();

// PoCL sizes its thread pool from the machine's cores unless POCL_MAX_PTHREAD_COUNT says otherwise:
// sets it to usable_cpus() when the user did not set it and the affinity mask is smaller than the
// machine. Must run before the OpenCL platform loads (main does it first).
void limit_opencl_threads_to_cpu_set();

}  // namespace splatcl
