# splatcl splats: a generated cube through the whole stage, then verify its output.
set(SPLATS_CUBE ${CMAKE_CURRENT_BINARY_DIR}/splats-cube.obj)
file(WRITE ${SPLATS_CUBE} "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n")
add_test(NAME cli.help_splats COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl splats \\[OPTIONS\\]" -- $<TARGET_FILE:splatcl> splats --help)
add_test(NAME cli.help_splats_verify COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl splats verify \\[OPTIONS\\]" -- $<TARGET_FILE:splatcl> splats verify --help)
set(SPLATS_BOUND_HOLDS "^check +two-sided bound holds: 0% of the surface uncovered, .* 0 beyond eps")
add_test(NAME cli.splats_cube COMMAND ${EXPECT_OUTPUT} --match "${SPLATS_BOUND_HOLDS}" --match "^samples +302 \\(grid:8"
         --ply ${CMAKE_CURRENT_BINARY_DIR}/splats-cube.ply 100 --file ${CMAKE_CURRENT_BINARY_DIR}/splats-cube.json "\"color_tolerance\": 40,"
         -- $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} --samples grid:8 --eps 0.002 --color-field hard --color-tol 40
         -o ${CMAKE_CURRENT_BINARY_DIR}/splats-cube.ply --stats ${CMAKE_CURRENT_BINARY_DIR}/splats-cube.json)
set_tests_properties(cli.splats_cube PROPERTIES FIXTURES_SETUP splats_cube)
add_test(NAME cli.splats_verify COMMAND ${EXPECT_OUTPUT} --match "^ok$" --match " 0 splats beyond eps$" -- $<TARGET_FILE:splatcl> splats verify ${SPLATS_CUBE} ${CMAKE_CURRENT_BINARY_DIR}/splats-cube.ply)
set_tests_properties(cli.splats_verify PROPERTIES FIXTURES_REQUIRED splats_cube)
# verify measures the surface, whoever made the splats: hand-made splat files with a known truth
# (tests/cli/make_test_splats.cpp) on the unit square pass, or fail naming the file and the bound.
add_executable(splatcl_make_test_splats cli/make_test_splats.cpp)
target_include_directories(splatcl_make_test_splats PRIVATE ${PROJECT_SOURCE_DIR}/host)
target_link_libraries(splatcl_make_test_splats PRIVATE splatcl_splats)
set(VERIFY_PLANE ${CMAKE_CURRENT_BINARY_DIR}/verify-plane.obj)
file(WRITE ${VERIFY_PLANE} "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
add_test(NAME cli.splats_verify_make_files COMMAND splatcl_make_test_splats ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(cli.splats_verify_make_files PROPERTIES FIXTURES_SETUP verify_files)
add_test(NAME cli.splats_verify_good COMMAND splatcl splats verify ${VERIFY_PLANE} ${CMAKE_CURRENT_BINARY_DIR}/verify-good.ply
         --points 100000 --json ${CMAKE_CURRENT_BINARY_DIR}/verify-good.json)
set_tests_properties(cli.splats_verify_good PROPERTIES FIXTURES_REQUIRED verify_files PASS_REGULAR_EXPRESSION "\nok\n")
add_test(NAME cli.error_splats_verify_lifted COMMAND ${EXPECT_ERROR} "verify-lifted.ply: fails the two-sided bound at eps 0.05 .*: 1 splat leaves the surface by more than eps \\(up to 3 eps\\)$"
         $<TARGET_FILE:splatcl> splats verify ${VERIFY_PLANE} ${CMAKE_CURRENT_BINARY_DIR}/verify-lifted.ply --points 100000)
add_test(NAME cli.error_splats_verify_hole COMMAND ${EXPECT_ERROR} "verify-hole.ply: fails the two-sided bound at eps 0.05 .*: surface not covered within eps"
         $<TARGET_FILE:splatcl> splats verify ${VERIFY_PLANE} ${CMAKE_CURRENT_BINARY_DIR}/verify-hole.ply --points 100000)
set_tests_properties(cli.error_splats_verify_lifted cli.error_splats_verify_hole PROPERTIES FIXTURES_REQUIRED verify_files)
# The builder's cube splats at a quarter of their eps: they reach beyond it (edges), so verify fails.
add_test(NAME cli.error_splats_verify_small_eps COMMAND ${EXPECT_ERROR} "splats-cube.ply: fails the two-sided bound at eps 0.0005 .*leave the surface by more than eps"
         $<TARGET_FILE:splatcl> splats verify ${SPLATS_CUBE} ${CMAKE_CURRENT_BINARY_DIR}/splats-cube.ply --eps 0.0005 --points 100000)
set_tests_properties(cli.error_splats_verify_small_eps PROPERTIES FIXTURES_REQUIRED splats_cube)
add_test(NAME cli.error_splats_verify_bad_points COMMAND ${EXPECT_ERROR} "--points must be 1000 to 20000000, not 10$"
         $<TARGET_FILE:splatcl> splats verify ${VERIFY_PLANE} ${CMAKE_CURRENT_BINARY_DIR}/verify-good.ply --points 10)
add_test(NAME cli.error_splats_verify_huge_points COMMAND ${EXPECT_ERROR} "--points must be 1000 to 20000000, not 99999999999"
         $<TARGET_FILE:splatcl> splats verify ${VERIFY_PLANE} ${CMAKE_CURRENT_BINARY_DIR}/verify-good.ply --points 99999999999)
add_test(NAME cli.error_splats_verify_bad_eps COMMAND ${EXPECT_ERROR} "--eps must be positive and within float range"
         $<TARGET_FILE:splatcl> splats verify ${VERIFY_PLANE} ${CMAKE_CURRENT_BINARY_DIR}/verify-good.ply --eps -1)
add_test(NAME cli.error_splats_verify_huge_eps COMMAND ${EXPECT_ERROR} "--eps must be positive and within float range .*, not 1e39"
         $<TARGET_FILE:splatcl> splats verify ${VERIFY_PLANE} ${CMAKE_CURRENT_BINARY_DIR}/verify-good.ply --eps 1e39)
# --json naming an input: refused before anything is read (it replaced the mesh with the report).
add_test(NAME cli.error_splats_verify_json_over_mesh COMMAND ${EXPECT_ERROR} "--json .*verify-plane.obj would overwrite the mesh"
         $<TARGET_FILE:splatcl> splats verify ${VERIFY_PLANE} ${CMAKE_CURRENT_BINARY_DIR}/verify-good.ply --json ${VERIFY_PLANE})
add_test(NAME cli.error_splats_verify_json_over_splats COMMAND ${EXPECT_ERROR} "--json .*verify-good.ply would overwrite the splat file"
         $<TARGET_FILE:splatcl> splats verify ${VERIFY_PLANE} ${CMAKE_CURRENT_BINARY_DIR}/verify-good.ply --json ${CMAKE_CURRENT_BINARY_DIR}/verify-good.ply)
add_test(NAME cli.splats_clip COMMAND ${EXPECT_OUTPUT} --match "${SPLATS_BOUND_HOLDS}" --ply ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-clip.ply 100
         -- $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} --samples grid:8 --eps 0.002 --color-field hard --color-tol 40 --clip
         -o ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-clip.ply)
set_tests_properties(cli.splats_clip PROPERTIES FIXTURES_SETUP splats_cube_clip)
add_test(NAME cli.splats_clip_verify COMMAND ${EXPECT_OUTPUT} --match "^ok$" --match " 0 splats beyond eps$" -- $<TARGET_FILE:splatcl> splats verify ${SPLATS_CUBE} ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-clip.ply)
set_tests_properties(cli.splats_clip_verify PROPERTIES FIXTURES_REQUIRED splats_cube_clip)
# --format 3dgs: the 3D Gaussian Splatting PLY read back with od and awk (header, count, per-Gaussian properties).
add_test(NAME cli.splats_3dgs COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/splats_3dgs_test.sh $<TARGET_FILE:splatcl> ${SPLATS_CUBE}
         ${CMAKE_CURRENT_BINARY_DIR}/cli-splats-3dgs ${CMAKE_CURRENT_BINARY_DIR}/splats-cube.ply ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-clip.ply)
set_tests_properties(cli.splats_3dgs PROPERTIES FIXTURES_REQUIRED "splats_cube;splats_cube_clip")
add_test(NAME cli.error_splats_bad_format COMMAND ${EXPECT_ERROR} "--format must be splatcl or 3dgs, not 'gsplat'" $<TARGET_FILE:splatcl>
         splats ${SPLATS_CUBE} -o out.ply --format gsplat)
# The outputs are checked before any work (the model is missing too: the output is named, not the model).
add_test(NAME cli.error_splats_output_dir_missing COMMAND ${EXPECT_ERROR} "cannot write -o .*no-such-dir/out.ply: directory .*no-such-dir does not exist"
         $<TARGET_FILE:splatcl> splats missing.obj -o ${CMAKE_CURRENT_BINARY_DIR}/no-such-dir/out.ply)
add_test(NAME cli.error_splats_output_is_directory COMMAND ${EXPECT_ERROR} "cannot write -o .*: it is a directory"
         $<TARGET_FILE:splatcl> splats missing.obj -o ${CMAKE_CURRENT_BINARY_DIR})
add_test(NAME cli.error_splats_same_output_twice COMMAND ${EXPECT_ERROR} "-o and --stats name the same file"
         $<TARGET_FILE:splatcl> splats missing.obj -o same.out --stats ./same.out)
# Nothing at -o when another output fails, before the work (--stats) or after it (--render).
foreach(mode stats render)
  add_test(NAME cli.error_splats_${mode}_fails_leaves_no_output COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/splats_outputs_test.sh ${mode}
           $<TARGET_FILE:splatcl> ${CMAKE_CURRENT_BINARY_DIR}/cli-splats-outputs-${mode} ${EXPECT_ERROR})
endforeach()
add_test(NAME cli.error_splats_bench_missing_models COMMAND ${EXPECT_ERROR} "models directory .*no-such-dir does not exist" $<TARGET_FILE:splatcl> bench splats --models no-such-dir)
add_test(NAME cli.splats_reference COMMAND ${EXPECT_OUTPUT} --match "${SPLATS_BOUND_HOLDS}" --match "\\(fit on reference\\)$" --ply ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-ref.ply 100
         -- $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} --samples grid:4 --reference -o ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-ref.ply)
add_test(NAME cli.error_splats_missing_model COMMAND ${EXPECT_ERROR} "cannot read mesh .*missing.obj" $<TARGET_FILE:splatcl> splats missing.obj -o out.ply)
add_test(NAME cli.error_splats_bad_samples COMMAND ${EXPECT_ERROR} "^splatcl: '--samples': 'grid:0' is not 'auto'" $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} -o out.ply --samples grid:0)
add_test(NAME cli.error_splats_bad_color_tol COMMAND ${EXPECT_ERROR} "--color-tol" $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} -o out.ply --color-tol 300)
# An eps beyond float range is named as such (not blamed on eps_diag); a missing texture image is
# named before the mesh's missing texture coordinates.
add_test(NAME cli.error_splats_eps_beyond_float COMMAND ${EXPECT_ERROR} "splats-cube.obj: eps 1e-300 is beyond float range"
         $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} -o out.ply --eps 1e-300)
add_test(NAME cli.error_splats_missing_texture COMMAND ${EXPECT_ERROR} "nope.png: No such file or directory$"
         $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} -o out.ply --texture nope.png)
# A folder named as the texture: the image reader's "no format reader" was the cause given.
add_test(NAME cli.error_splats_texture_is_a_directory COMMAND ${EXPECT_ERROR} "cannot read texture .*/tests: it is a directory$"
         $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} -o out.ply --texture ${CMAKE_CURRENT_BINARY_DIR})
add_test(NAME cli.error_splats_no_output COMMAND ${EXPECT_ERROR} "-o OUT.ply" $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE})
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/splats-broken.ply "ply\nformat ascii 1.0\nend_header\n")
add_test(NAME cli.error_splats_verify_broken COMMAND ${EXPECT_ERROR} "splats-broken.ply" $<TARGET_FILE:splatcl> splats verify ${SPLATS_CUBE} ${CMAKE_CURRENT_BINARY_DIR}/splats-broken.ply)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/splats-nan.obj "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")
add_test(NAME cli.error_splats_nan_model COMMAND ${EXPECT_ERROR} "splats-nan.obj: the mesh has no faces .*non-finite coordinate" $<TARGET_FILE:splatcl>
         splats ${CMAKE_CURRENT_BINARY_DIR}/splats-nan.obj -o ${CMAKE_CURRENT_BINARY_DIR}/splats-nan.ply)
# Mesh hygiene (core/mesh.hpp): counted problems are one warning line, and with --strict one error line naming the model.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/splats-bad-face.obj "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\nf 1 2 99\n")
add_test(NAME cli.error_splats_strict_bad_face COMMAND ${EXPECT_ERROR} "splats-bad-face.obj: 1 face with an index out of range or unreadable dropped \\(--strict\\)$"
         $<TARGET_FILE:splatcl> splats ${CMAKE_CURRENT_BINARY_DIR}/splats-bad-face.obj --strict -o ${CMAKE_CURRENT_BINARY_DIR}/splats-bad-face.ply)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/splats-inside-out.obj "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 2 3 4 1\nf 8 7 6 5\nf 5 6 2 1\nf 7 8 4 3\nf 6 7 3 2\nf 4 8 5 1\n")
set(SPLATS_INSIDE_OUT ${CMAKE_CURRENT_BINARY_DIR}/splats-inside-out.obj)
# The faces are turned outward on loading (--strict refuses a model that needed it); with
# --keep-winding they are taken as the file winds them.
add_test(NAME cli.error_splats_strict_inside_out COMMAND ${EXPECT_ERROR}
         "splats-inside-out.obj: 6 faces turned to agree with their neighbours' winding \\(closed parts outward\\) \\(--strict\\)$"
         $<TARGET_FILE:splatcl> splats ${SPLATS_INSIDE_OUT} --strict -o ${CMAKE_CURRENT_BINARY_DIR}/splats-inside-out.ply)
add_test(NAME cli.error_splats_strict_inside_out_kept COMMAND ${EXPECT_ERROR} "splats-inside-out.obj: faces point inward .*\\(--strict\\)$"
         $<TARGET_FILE:splatcl> splats ${SPLATS_INSIDE_OUT} --strict --keep-winding -o ${CMAKE_CURRENT_BINARY_DIR}/splats-inside-out.ply)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/splats-truncated.off "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n")
add_test(NAME cli.error_splats_truncated_off COMMAND ${EXPECT_ERROR} "cannot read mesh .*splats-truncated.off: truncated OFF"
         $<TARGET_FILE:splatcl> splats ${CMAKE_CURRENT_BINARY_DIR}/splats-truncated.off -o ${CMAKE_CURRENT_BINARY_DIR}/splats-truncated.ply)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/splats-no-end-header.ply "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n0\n1\n2\n")
add_test(NAME cli.error_splats_ply_no_end_header COMMAND ${EXPECT_ERROR} "splats-no-end-header.ply: PLY header has no end_header"
         $<TARGET_FILE:splatcl> splats ${CMAKE_CURRENT_BINARY_DIR}/splats-no-end-header.ply -o ${CMAKE_CURRENT_BINARY_DIR}/splats-no-end-header-out.ply)
set_tests_properties(cli.error_splats_ply_no_end_header PROPERTIES TIMEOUT 10)
# OpenImageIO is a module loaded on first use: without it, an image output fails its check before any work, in one line.
add_test(NAME cli.error_image_module_missing COMMAND ${EXPECT_ERROR} "cannot write .*splats-no-module.png: the image module is missing \\(.*no-such-module.so"
         $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} --samples grid:4 -o ${CMAKE_CURRENT_BINARY_DIR}/splats-no-module.ply
         --render ${CMAKE_CURRENT_BINARY_DIR}/splats-no-module.png)
set_tests_properties(cli.error_image_module_missing PROPERTIES ENVIRONMENT SPLATCL_OIIO_MODULE=${CMAKE_CURRENT_BINARY_DIR}/no-such-module.so)
add_test(NAME cli.error_splats_output_is_model COMMAND ${EXPECT_ERROR} "-o .*csm-overwrite-me.obj would overwrite the model" $<TARGET_FILE:splatcl>
         splats ${CMAKE_CURRENT_BINARY_DIR}/csm-overwrite-me.obj -o ${CMAKE_CURRENT_BINARY_DIR}/csm-overwrite-me.obj)
add_test(NAME cli.error_splats_output_dir_is_file COMMAND ${EXPECT_ERROR} "cannot write -o .*csm-overwrite-me.obj/out.ply: .*csm-overwrite-me.obj is a file, not a directory"
         $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} -o ${CMAKE_CURRENT_BINARY_DIR}/csm-overwrite-me.obj/out.ply)
# --max-covered is honoured with --thesis-only (it was ignored: the thesis's growth had no cap).
add_test(NAME cli.splats_thesis_max_covered COMMAND ${EXPECT_OUTPUT} --file ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-thesis.json "\"largest_covered_set\": 40,"
         --file ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-thesis.json "\"max_covered\": 40,"
         -- $<TARGET_FILE:splatcl> splats ${SPLATS_CUBE} --samples grid:8 --eps 0.002 --thesis-only --crease-angle 60 --max-covered 40
         -o ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-thesis.ply --stats ${CMAKE_CURRENT_BINARY_DIR}/splats-cube-thesis.json)
# An eps beyond the bounding-box diagonal is capped at it: a 1.5 x 1 x 1 box fitted at 3 x its
# diagonal came out with holes (0.02 % uncovered by a splat facing its way) and wrote nothing.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/splats-long-box.obj
     "v 0 0 0\nv 1.5 0 0\nv 0 1 0\nv 1.5 1 0\nv 0 0 1\nv 1.5 0 1\nv 0 1 1\nv 1.5 1 1\nf 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n")
add_test(NAME cli.splats_eps_beyond_the_diagonal_is_capped COMMAND ${EXPECT_OUTPUT}
         --match "^eps +2\\.06155 \\(1 of the diagonal; 6\\.18466 asked, capped at the diagonal\\)" --match "^check +two-sided bound holds"
         --file ${CMAKE_CURRENT_BINARY_DIR}/splats-long-box.json "\"eps_requested\": 6\\.1846[0-9]*,"
         -- $<TARGET_FILE:splatcl> splats ${CMAKE_CURRENT_BINARY_DIR}/splats-long-box.obj --eps-diag 3
         -o ${CMAKE_CURRENT_BINARY_DIR}/splats-long-box.ply --stats ${CMAKE_CURRENT_BINARY_DIR}/splats-long-box.json)
# ... and an eps within the diagonal that rounds down in float is not called capped.
add_test(NAME cli.splats_eps_within_the_diagonal_is_not_capped COMMAND ${EXPECT_OUTPUT}
         --match "^eps +0\\.01 \\([0-9.]+ of the diagonal\\)" --no-match "capped"
         -- $<TARGET_FILE:splatcl> splats ${CMAKE_CURRENT_BINARY_DIR}/splats-long-box.obj --eps 0.01
         -o ${CMAKE_CURRENT_BINARY_DIR}/splats-long-box-fine.ply)
