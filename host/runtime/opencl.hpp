#pragma once
// The single place that includes the OpenCL C++ bindings, so every target sees the same settings.
#ifndef CL_HPP_TARGET_OPENCL_VERSION
#define CL_HPP_TARGET_OPENCL_VERSION 300
#endif
#ifndef CL_HPP_MIN_REQUIRED_OPENCL_VERSION
#define CL_HPP_MIN_REQUIRED_OPENCL_VERSION 120
#endif
#ifndef CL_HPP_ENABLE_EXCEPTIONS
#define CL_HPP_ENABLE_EXCEPTIONS
#endif
#include <CL/opencl.hpp>
