// The source of splatcl_precompiled (cmake/build_time.cmake): the target exists to compile
// the precompiled headers that the project's other targets reuse.
