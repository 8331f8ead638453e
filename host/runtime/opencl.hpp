#pragma once
// The single place that includes the OpenCL C++ bindings, so every target sees the same settings.
#ifndef CL_HPP_TARGET_OPENCL_VERSION
#define CL_HPP_TARGET_OPENCL_VERSION 300
#endif
// The oldest platform version the bindings may meet. The header reads CL_HPP_MINIMUM_OPENCL_VERSION
// (default 200): at 200 cl::CommandQueue always calls the 2.0 entry point
// clCreateCommandQueueWithProperties, which hangs through ocl-icd on a 1.2 platform (Oclgrind). At
// 110 it checks the platform's version and uses clCreateCommandQueue there. (120 does not compile
// with Debian 12's opencl-clhpp.)
#ifndef CL_HPP_MINIMUM_OPENCL_VERSION
#define CL_HPP_MINIMUM_OPENCL_VERSION 110
#endif
#ifndef CL_HPP_ENABLE_EXCEPTIONS
#define CL_HPP_ENABLE_EXCEPTIONS
#endif
#include <CL/opencl.hpp>
