# splatcl ao: the test model spot.obj's vertices under two instances of the cube's CSM (and the
# reference path with the ground plane), then bad input: one line each.
# Needs SPLATS_CUBE (splats.cmake) and CSM_OUT with its csm_cube fixture (csm.cmake).
set(AO_MODEL ${SPLATCL_MODELS_DIR}/spot.obj)
add_test(NAME cli.help_ao COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl ao \\[OPTIONS\\]" -- $<TARGET_FILE:splatcl> ao --help)
# Every vertex of spot (2930) is a receiver; the AO stays in [0, 1] with some vertices occluded.
set(AO_SPOT_RANGE "^ao +mean 0\\.[0-9]+, min 0\\.[0-9]+, max 1\\.0000 \\(1 = unoccluded\\)$")
# With the ground plane an unoccluded vertex reads (1 + n.y) / 2, the sky's share above the floor:
# 1 only for a normal straight up.
set(AO_SPOT_GROUND_RANGE "^ao +mean 0\\.[0-9]+, min 0\\.[0-9]+, max (0\\.9[0-9]+|1\\.0000) \\(1 = unoccluded\\)$")
add_test(NAME cli.ao_spot COMMAND ${NEEDS_FILE} ${AO_MODEL} ${EXPECT_OUTPUT} --match "^receivers +2930 vertices of .*spot.obj; 2 occluder instance\\(s\\) of 1 CSM file\\(s\\)$"
         --match "^sampling +16 directions per vertex, pattern set latin-hypercube" --match "${AO_SPOT_RANGE}" --ply ${CMAKE_CURRENT_BINARY_DIR}/ao-spot.ply 2930
         -- $<TARGET_FILE:splatcl> ao ${AO_MODEL} --occluder ${CSM_OUT} --occluder-transform 0,1.2,0
         --occluder ${CSM_OUT} --occluder-transform 1.5,0,0,0,45,0 --pattern lhs --samples 16 -o ${CMAKE_CURRENT_BINARY_DIR}/ao-spot.ply)
add_test(NAME cli.ao_spot_reference_ground COMMAND ${NEEDS_FILE} ${AO_MODEL} ${EXPECT_OUTPUT} --match "; ground plane on$" --match "${AO_SPOT_GROUND_RANGE}"
         --match "on the native reference" --ply ${CMAKE_CURRENT_BINARY_DIR}/ao-spot-ground.ply 2930
         -- $<TARGET_FILE:splatcl> ao ${AO_MODEL} --occluder ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-compact.csm --ground-plane --pattern stratified --reference
         -o ${CMAKE_CURRENT_BINARY_DIR}/ao-spot-ground.ply)
# An inside-out receiver is turned outward on loading: the cube's own AO, 1 at every corner lifted a
# texel (0.99 on the surface), against 0.11 with --keep-winding, whose inward corner normals look
# into the cube (0.21 on the surface).
add_test(NAME cli.ao_inside_out_receiver COMMAND ${EXPECT_OUTPUT} --match "^ao +mean (0\\.9[0-9]+|1\\.0000), min (0\\.9[0-9]+|1\\.0000), max 1\\.0000"
         --match "splats-inside-out.obj: 6 faces turned to agree with their neighbours' winding \\(closed parts outward\\)$"
         -- $<TARGET_FILE:splatcl> ao ${SPLATS_INSIDE_OUT} --occluder ${CSM_OUT} -o ${CMAKE_CURRENT_BINARY_DIR}/ao-inside-out.ply)
add_test(NAME cli.ao_inside_out_receiver_kept COMMAND ${EXPECT_OUTPUT} --match "^ao +mean 0\\.[0-4][0-9]+, min 0\\.[0-9]+, max 0\\.[0-4]"
         --match "faces point inward" -- $<TARGET_FILE:splatcl> ao ${SPLATS_INSIDE_OUT} --occluder ${CSM_OUT} --keep-winding
         -o ${CMAKE_CURRENT_BINARY_DIR}/ao-inside-out-kept.ply)
set_tests_properties(cli.ao_spot cli.ao_spot_reference_ground cli.ao_inside_out_receiver cli.ao_inside_out_receiver_kept
                     PROPERTIES FIXTURES_REQUIRED csm_cube SKIP_RETURN_CODE 77)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/ao-nan.obj "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/ao-empty.obj "# no geometry\n")
string(REPEAT "corrupt " 40 AO_CORRUPT_BODY)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/ao-corrupt.csm "SPLATCSM${AO_CORRUPT_BODY}")
add_test(NAME cli.error_ao_no_occluder COMMAND ${EXPECT_ERROR} "at least one --occluder" $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE} -o out.ply)
add_test(NAME cli.error_ao_no_output COMMAND ${EXPECT_ERROR} "-o OUT.ply" $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE} --occluder ${CSM_OUT})
add_test(NAME cli.error_ao_missing_csm COMMAND ${EXPECT_ERROR} "cannot read missing.csm" $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE} --occluder missing.csm -o out.ply)
add_test(NAME cli.error_ao_truncated_csm COMMAND ${EXPECT_ERROR} "csm-truncated.csm: not a .csm file" $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE}
         --occluder ${CMAKE_CURRENT_BINARY_DIR}/csm-truncated.csm -o out.ply)
add_test(NAME cli.error_ao_corrupt_csm COMMAND ${EXPECT_ERROR} "ao-corrupt.csm: " $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE}
         --occluder ${CMAKE_CURRENT_BINARY_DIR}/ao-corrupt.csm -o out.ply)
add_test(NAME cli.error_ao_bad_transform COMMAND ${EXPECT_ERROR} "bad occluder transform '1,2'" $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE}
         --occluder ${CSM_OUT} --occluder-transform 1,2 -o out.ply)
add_test(NAME cli.error_ao_transform_count COMMAND ${EXPECT_ERROR} "2 --occluder-transform for 1 --occluder" $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE}
         --occluder ${CSM_OUT} --occluder-transform 0,0,0 --occluder-transform 1,0,0 -o out.ply)
add_test(NAME cli.error_ao_bad_pattern COMMAND ${EXPECT_ERROR} "unknown pattern set 'sobol'" $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE}
         --occluder ${CSM_OUT} --pattern sobol -o out.ply)
add_test(NAME cli.error_ao_nan_mesh COMMAND ${EXPECT_ERROR} "ao-nan.obj" $<TARGET_FILE:splatcl> ao ${CMAKE_CURRENT_BINARY_DIR}/ao-nan.obj
         --occluder ${CSM_OUT} -o out.ply)
add_test(NAME cli.error_ao_empty_mesh COMMAND ${EXPECT_ERROR} "ao-empty.obj" $<TARGET_FILE:splatcl> ao ${CMAKE_CURRENT_BINARY_DIR}/ao-empty.obj
         --occluder ${CSM_OUT} -o out.ply)
add_test(NAME cli.error_ao_missing_receiver COMMAND ${EXPECT_ERROR} "missing.obj" $<TARGET_FILE:splatcl> ao missing.obj --occluder ${CSM_OUT} -o out.ply)
set_tests_properties(cli.error_ao_no_output cli.error_ao_truncated_csm cli.error_ao_bad_transform cli.error_ao_transform_count
                     cli.error_ao_bad_pattern cli.error_ao_nan_mesh cli.error_ao_empty_mesh cli.error_ao_missing_receiver
                     PROPERTIES FIXTURES_REQUIRED csm_cube)
add_test(NAME cli.error_ao_output_is_occluder COMMAND ${EXPECT_ERROR} "-o .*ao-corrupt.csm would overwrite the occluder" $<TARGET_FILE:splatcl>
         ao ${SPLATS_CUBE} --occluder ${CMAKE_CURRENT_BINARY_DIR}/ao-corrupt.csm -o ${CMAKE_CURRENT_BINARY_DIR}/ao-corrupt.csm)
add_test(NAME cli.error_ao_output_extension COMMAND ${EXPECT_ERROR} "-o out.obj: the file must end in .ply" $<TARGET_FILE:splatcl>
         ao ${SPLATS_CUBE} --occluder ${CSM_OUT} -o out.obj)
add_test(NAME cli.error_ao_transform_beyond_float COMMAND ${EXPECT_ERROR} "'1e39' is not a finite number in float range" $<TARGET_FILE:splatcl>
         ao ${SPLATS_CUBE} --occluder ${CSM_OUT} --occluder-transform 1e39,0,0 -o out.ply)
# A singular placement named by its text (it failed later as "an occluder placement is not invertible", naming none).
add_test(NAME cli.error_ao_singular_transform COMMAND ${EXPECT_ERROR} "bad occluder transform '0,0,0,1,0,1,0,0,0,0,1,0,0,0,0,1': an occluder placement is not invertible$"
         $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE} --occluder ${CSM_OUT} --occluder-transform 0,0,0,1,0,1,0,0,0,0,1,0,0,0,0,1 -o out.ply)
set_tests_properties(cli.error_ao_singular_transform PROPERTIES FIXTURES_REQUIRED csm_cube)
# --bias 1e39 reads as the float inf: the message says what is wrong with what was typed.
add_test(NAME cli.error_ao_bias_beyond_float COMMAND ${EXPECT_ERROR} "ao: --bias inf is not a texel count in 0..1000$"
         $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE} --occluder ${CSM_OUT} --bias 1e39 -o out.ply)
set_tests_properties(cli.error_ao_bias_beyond_float PROPERTIES FIXTURES_REQUIRED csm_cube)
# A rotation beyond 100 turns is refused (1e30 degrees turned the occluder at random), and a
# placement where floats step by more than 1e-4 of the occluder's size is named in a warning (the
# placement is applied in float: 1e6 + 0.6 became 1000000.625).
add_test(NAME cli.error_ao_rotation_beyond_100_turns COMMAND ${EXPECT_ERROR} "bad occluder transform '0,0,0,1e30,0,0': rotation 1e\\+30 is beyond 100 turns"
         $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE} --occluder ${CSM_OUT} --occluder-transform 0,0,0,1e30,0,0 -o out.ply)
add_test(NAME cli.ao_far_placement_warns COMMAND ${EXPECT_OUTPUT}
         --match "^splatcl: warning: --occluder 1 \\(.*\\): placed where floats step by 0.0625 \\([0-9.]+ % of its [0-9.]+ bounding diameter\\)"
         -- $<TARGET_FILE:splatcl> ao ${SPLATS_CUBE} --occluder ${CSM_OUT} --occluder-transform 1000000,1000000.6,1000000
         -o ${CMAKE_CURRENT_BINARY_DIR}/ao-far-placement.ply)
set_tests_properties(cli.error_ao_rotation_beyond_100_turns cli.ao_far_placement_warns PROPERTIES FIXTURES_REQUIRED csm_cube)
