# splatcl csm: a generated cube built, described, verified (losslessness), then bad input.
set(CSM_OUT ${CMAKE_CURRENT_BINARY_DIR}/csm-cube.csm)
add_test(NAME cli.help_csm COMMAND splatcl csm --help)
add_test(NAME cli.help_csm_build COMMAND splatcl csm build --help)
add_test(NAME cli.csm_build_cube COMMAND splatcl csm build ${SPLATS_CUBE} -o ${CSM_OUT} --maps 256 --res 32 --batch 50
         --coherence ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-coherence.png)
set_tests_properties(cli.csm_build_cube PROPERTIES FIXTURES_SETUP csm_cube)
add_test(NAME cli.csm_build_cube_compact COMMAND splatcl csm build ${SPLATS_CUBE} -o ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-compact.csm
         --maps 128 --res 16 --dist ao --order zigzag-v --encoding compact --single-hit exact)
set_tests_properties(cli.csm_build_cube_compact PROPERTIES FIXTURES_SETUP csm_cube)
add_test(NAME cli.csm_info COMMAND splatcl csm info ${CSM_OUT})
add_test(NAME cli.csm_verify COMMAND splatcl csm verify ${CSM_OUT} ${SPLATS_CUBE})
add_test(NAME cli.csm_verify_compact COMMAND splatcl csm verify ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-compact.csm ${SPLATS_CUBE} --reference)
set_tests_properties(cli.csm_info cli.csm_verify cli.csm_verify_compact PROPERTIES FIXTURES_REQUIRED csm_cube)
# Both capture methods: a ray-cast build verifies by the method recorded in its header; a bad method name is an error.
add_test(NAME cli.csm_build_cube_raycast COMMAND splatcl csm build ${SPLATS_CUBE} -o ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-raycast.csm
         --maps 64 --res 16 --capture raycast)
set_tests_properties(cli.csm_build_cube_raycast PROPERTIES FIXTURES_SETUP csm_cube_raycast)
add_test(NAME cli.csm_verify_raycast COMMAND splatcl csm verify ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-raycast.csm ${SPLATS_CUBE})
set_tests_properties(cli.csm_verify_raycast PROPERTIES PASS_REGULAR_EXPRESSION "recaptured by raycast, as recorded in the file")
set_tests_properties(cli.csm_verify_raycast PROPERTIES FIXTURES_REQUIRED csm_cube_raycast)
add_test(NAME cli.error_csm_bad_capture COMMAND ${EXPECT_ERROR} "unknown capture method 'rays'" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o out.csm --capture rays)
add_test(NAME cli.error_csm_missing_model COMMAND ${EXPECT_ERROR} "cannot read mesh .*missing.obj" $<TARGET_FILE:splatcl> csm build missing.obj -o out.csm)
add_test(NAME cli.error_csm_no_output COMMAND ${EXPECT_ERROR} "-o OUT.csm" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE})
add_test(NAME cli.error_csm_bad_maps COMMAND ${EXPECT_ERROR} "not a perfect square" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o out.csm --maps 1000)
add_test(NAME cli.error_csm_bad_order COMMAND ${EXPECT_ERROR} "unknown map order 'spiral'" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o out.csm --order spiral)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/csm-degenerate.obj "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
add_test(NAME cli.error_csm_degenerate_model COMMAND ${EXPECT_ERROR} "csm-degenerate.obj: every face is degenerate" $<TARGET_FILE:splatcl>
         csm build ${CMAKE_CURRENT_BINARY_DIR}/csm-degenerate.obj -o out.csm --maps 16 --res 8)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/csm-truncated.csm "SPLATCSM")
add_test(NAME cli.error_csm_truncated COMMAND ${EXPECT_ERROR} "csm-truncated.csm: not a .csm file" $<TARGET_FILE:splatcl> csm info ${CMAKE_CURRENT_BINARY_DIR}/csm-truncated.csm)
add_test(NAME cli.error_csm_missing_file COMMAND ${EXPECT_ERROR} "cannot read missing.csm" $<TARGET_FILE:splatcl> csm verify missing.csm)
# splatcl csm quality: the shadow-quality study on the generated cube, then a bad filter name.
add_test(NAME cli.csm_quality_cube COMMAND splatcl csm quality ${SPLATS_CUBE} --maps 64 --res 16 --views 2 --image 32 --filter cross-map)
add_test(NAME cli.error_csm_quality_bad_filter COMMAND ${EXPECT_ERROR} "unknown filter 'gauss'" $<TARGET_FILE:splatcl> csm quality ${SPLATS_CUBE} --maps 64 --res 16 --filter gauss)

# csm build --mode: the thesis's alternatives (sizes only, every sample checked), csm analyze.
add_test(NAME cli.csm_mode_per_map COMMAND splatcl csm build ${SPLATS_CUBE} --mode per-map --pixel-order zigzag-h --maps 64 --res 16)
add_test(NAME cli.csm_mode_hilbert_3d COMMAND splatcl csm build ${SPLATS_CUBE} --mode hilbert-3d --maps 36 --res 8)
add_test(NAME cli.csm_mode_hilbert_4d COMMAND splatcl csm build ${SPLATS_CUBE} --mode hilbert-4d --maps 64 --res 8 --reference)
add_test(NAME cli.csm_analyze COMMAND splatcl csm analyze ${SPLATS_CUBE} --maps 64 --res 16 --kmeans 4 --kmeans 64 --wavelet)
add_test(NAME cli.error_csm_bad_mode COMMAND ${EXPECT_ERROR} "unknown compression mode 'octree'" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} --mode octree)
add_test(NAME cli.error_csm_mode_output COMMAND ${EXPECT_ERROR} "only measures sizes" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} --mode per-map -o out.csm)
add_test(NAME cli.error_csm_mode_hilbert_res COMMAND ${EXPECT_ERROR} "power-of-two resolution, not 12" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE}
         --mode per-map --maps 16 --res 12)
add_test(NAME cli.error_csm_analyze_nothing COMMAND ${EXPECT_ERROR} "--kmeans K" $<TARGET_FILE:splatcl> csm analyze ${SPLATS_CUBE} --maps 16 --res 8)
add_test(NAME cli.error_csm_analyze_big_k COMMAND ${EXPECT_ERROR} "k = 32 must be between 1 and the map count 16" $<TARGET_FILE:splatcl> csm analyze
         ${SPLATS_CUBE} --maps 16 --res 8 --kmeans 32)
