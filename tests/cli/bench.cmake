# splatcl bench: the csm suite in --quick mode to JSON and CSV (on the test model stanford-bunny.obj,
# skipped without it), then report, compare, plot and errors.
set(BENCH_MODEL ${SPLATCL_MODELS_DIR}/stanford-bunny.obj)
set(BENCH_QUICK ${CMAKE_CURRENT_BINARY_DIR}/bench-csm-quick)
foreach(command csm plot compare report)
  add_test(NAME cli.help_bench_${command} COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl bench ${command} \\[OPTIONS\\]" -- $<TARGET_FILE:splatcl> bench ${command} --help)
endforeach()
add_test(NAME cli.bench_csm_quick COMMAND ${NEEDS_FILE} ${BENCH_MODEL} ${EXPECT_OUTPUT} --file ${BENCH_QUICK}.json "\"suite\": \"csm\""
         --file ${BENCH_QUICK}.csv "^csm,capture,opencl,.*,stanford-bunny," --file ${BENCH_QUICK}.csv "^csm,ao,reference,host,"
         -- $<TARGET_FILE:splatcl> bench csm --quick --device cpu --json ${BENCH_QUICK}.json --csv ${BENCH_QUICK}.csv)
set_tests_properties(cli.bench_csm_quick PROPERTIES FIXTURES_SETUP bench_csm_quick SKIP_RETURN_CODE 77)
add_test(NAME cli.bench_report_quick COMMAND ${NEEDS_FILE} ${BENCH_MODEL} ${EXPECT_OUTPUT} --match "^### csm$"
         --match "^\\| capture model=stanford-bunny res=32 +\\| opencl raycast +\\| +8192 rays \\|"
         -- $<TARGET_FILE:splatcl> bench report ${BENCH_QUICK}.json)
# A results file against itself: every record matched, none slower, every change +0.0 %.
add_test(NAME cli.bench_compare_identical COMMAND ${NEEDS_FILE} ${BENCH_MODEL} ${EXPECT_OUTPUT} --match "^0 of [1-9][0-9]* matched records regressed by more than 0 %"
         --no-match "\\| [-+]([1-9][0-9]*\\.[0-9]|0\\.[1-9]) % \\|" --match "\\| \\+0\\.0 % \\|" --no-match "^only in"
         -- $<TARGET_FILE:splatcl> bench compare ${BENCH_QUICK}.json ${BENCH_QUICK}.json --threshold 0)
add_test(NAME cli.bench_compare_csv_with_json COMMAND ${NEEDS_FILE} ${BENCH_MODEL} ${EXPECT_OUTPUT} --match "^0 of [1-9][0-9]* matched records regressed by more than 0 %"
         -- $<TARGET_FILE:splatcl> bench compare ${BENCH_QUICK}.csv ${BENCH_QUICK}.json --threshold 0)
set_tests_properties(cli.bench_report_quick cli.bench_compare_identical cli.bench_compare_csv_with_json PROPERTIES FIXTURES_REQUIRED bench_csm_quick
                     SKIP_RETURN_CODE 77)
find_program(GNUPLOT_PROGRAM gnuplot)
if(GNUPLOT_PROGRAM)
  add_test(NAME cli.bench_plot_quick COMMAND ${NEEDS_FILE} ${BENCH_MODEL} ${EXPECT_OUTPUT} --match "^wrote .*bench-plots/throughput-csm.png$"
           --file ${CMAKE_CURRENT_BINARY_DIR}/bench-plots/throughput-csm.dat "capture" -- $<TARGET_FILE:splatcl> bench plot ${BENCH_QUICK}.json -o ${CMAKE_CURRENT_BINARY_DIR}/bench-plots)
  set_tests_properties(cli.bench_plot_quick PROPERTIES FIXTURES_REQUIRED bench_csm_quick SKIP_RETURN_CODE 77)
endif()
set(BENCH_RECORD "\"suite\": \"csm\", \"case\": \"capture\", \"impl\": \"opencl\", \"device\": \"dev\", \"size\": 1000, \"size_unit\": \"rays\", \"runs\": 3, \"throughput\": 1e5, \"throughput_unit\": \"rays/s\"")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/bench-fast.json "{\"machine\": {}, \"records\": [{${BENCH_RECORD}, \"median_ms\": 10, \"min_ms\": 9, \"max_ms\": 11}]}\n")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/bench-slow.json "{\"machine\": {}, \"records\": [{${BENCH_RECORD}, \"median_ms\": 12, \"min_ms\": 11, \"max_ms\": 13}]}\n")
# The median slower by 20 %, the fastest run not: noise, not a regression.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/bench-noisy.json "{\"machine\": {}, \"records\": [{${BENCH_RECORD}, \"median_ms\": 12, \"min_ms\": 9, \"max_ms\": 30}]}\n")
add_test(NAME cli.bench_compare_noise_is_no_regression COMMAND ${EXPECT_OUTPUT} --match "^0 of 1 matched records regressed by more than 10 %"
         -- $<TARGET_FILE:splatcl> bench compare ${CMAKE_CURRENT_BINARY_DIR}/bench-noisy.json ${CMAKE_CURRENT_BINARY_DIR}/bench-fast.json --threshold 10)
# Unrelated files: exit status 2 (no comparison), not 1 (regressions).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/bench-other-suite.json "{\"machine\": {}, \"records\": [{\"suite\": \"primitives\", \"case\": \"scan\", \"impl\": \"opencl\", \"device\": \"dev\", \"runs\": 1, \"median_ms\": 1, \"min_ms\": 1, \"max_ms\": 1}]}\n")
add_test(NAME cli.bench_compare_no_match_exits_2 COMMAND sh -c "\"$1\" bench compare \"$2\" \"$3\" 2>\"$2.err\"; test $? -eq 2 && grep -q 'splatcl: no record matches one in .*bench-fast.json' \"$2.err\""
         sh $<TARGET_FILE:splatcl> ${CMAKE_CURRENT_BINARY_DIR}/bench-other-suite.json ${CMAKE_CURRENT_BINARY_DIR}/bench-fast.json)
add_test(NAME cli.error_bench_regression COMMAND ${EXPECT_ERROR} "1 regression\\(s\\) beyond 10 % against .*bench-fast.json" $<TARGET_FILE:splatcl>
         bench compare ${CMAKE_CURRENT_BINARY_DIR}/bench-slow.json ${CMAKE_CURRENT_BINARY_DIR}/bench-fast.json --threshold 10)
add_test(NAME cli.bench_within_threshold COMMAND ${EXPECT_OUTPUT} --match "^0 of 1 matched records regressed by more than 25 %" --match "\\| \\+20\\.0 % \\|"
         -- $<TARGET_FILE:splatcl> bench compare ${CMAKE_CURRENT_BINARY_DIR}/bench-slow.json ${CMAKE_CURRENT_BINARY_DIR}/bench-fast.json --threshold 25)
# Fault injection: the GPU shape's compaction scatter skipped (a marker instead of the kernel). The
# output buffer, shared with the CPU shape, still held that shape's correct result, and the run
# passed and recorded a speed for a kernel that never ran; now it is poisoned before each shape.
add_test(NAME cli.error_bench_kernel_that_writes_nothing COMMAND ${EXPECT_ERROR} "bench compact-flagged opencl \\(gpu shape\\): output differs from the reference"
         env SPLATCL_TEST_SKIP_KERNEL=compact_scatter_gpu $<TARGET_FILE:splatcl> bench primitives --size 4096 --runs 1 --warmup 0)
add_test(NAME cli.error_bench_bad_scaling COMMAND ${EXPECT_ERROR} "unknown scaling 'cores'" $<TARGET_FILE:splatcl> bench csm --scaling cores)
add_test(NAME cli.error_bench_missing_results COMMAND ${EXPECT_ERROR} "cannot read .*missing.json" $<TARGET_FILE:splatcl> bench plot missing.json -o plots)
add_test(NAME cli.error_bench_json_dir COMMAND ${EXPECT_ERROR} "cannot write --json .*no-such-dir" $<TARGET_FILE:splatcl> bench csm --json no-such-dir/x.json)
add_test(NAME cli.error_bench_csm_missing_models COMMAND ${EXPECT_ERROR} "models directory .*no-such-dir does not exist" $<TARGET_FILE:splatcl>
         bench csm --quick --models no-such-dir)
add_test(NAME cli.error_bench_bad_device COMMAND ${EXPECT_ERROR} "no OpenCL device matches" $<TARGET_FILE:splatcl> bench csm --quick --device no-such-device)
# Refused before any run: an output that names the --compare baseline (it was written over, then
# the run compared with itself: "0 regressed"); a missing model of a later suite (the earlier suites
# ran first, and their results were lost); --plot without gnuplot.
add_test(NAME cli.error_bench_output_is_baseline COMMAND ${EXPECT_ERROR} "--json .*bench-fast.json would overwrite the --compare baseline"
         $<TARGET_FILE:splatcl> bench primitives --quick --json ${CMAKE_CURRENT_BINARY_DIR}/bench-fast.json --compare ${CMAKE_CURRENT_BINARY_DIR}/bench-fast.json)
add_test(NAME cli.error_bench_missing_model_first COMMAND ${EXPECT_ERROR} "bench splats: models directory .*no-such-dir does not exist"
         $<TARGET_FILE:splatcl> bench --quick --models no-such-dir)
add_test(NAME cli.error_bench_run_plot_without_gnuplot COMMAND ${EXPECT_ERROR} "--plot: gnuplot not found on PATH" env PATH=/nonexistent
         $<TARGET_FILE:splatcl> bench primitives --quick --plot ${CMAKE_CURRENT_BINARY_DIR}/bench-plots-run-nognuplot)
add_test(NAME cli.error_bench_plot_without_gnuplot COMMAND ${EXPECT_ERROR} "gnuplot not found on PATH: .*, then run gnuplot .*bench-plots-nognuplot/plots.gp$" env PATH=/nonexistent
         $<TARGET_FILE:splatcl> bench plot ${CMAKE_CURRENT_BINARY_DIR}/bench-fast.json -o ${CMAKE_CURRENT_BINARY_DIR}/bench-plots-nognuplot)
# splatcl bench tune and the tuning database: a typo in --kernel fails before any run; a database
# ($SPLATCL_TUNING) that cannot be read, or whose record the device cannot run, is one line naming it.
add_test(NAME cli.help_bench_tune COMMAND splatcl bench tune --help)
add_test(NAME cli.error_bench_tune_kernel COMMAND ${EXPECT_ERROR} "unknown kernel 'fft' to tune \\(one of: scan, compact, radix-sort\\)"
         $<TARGET_FILE:splatcl> bench tune --kernel fft -o ${CMAKE_CURRENT_BINARY_DIR}/tune-typo.json)
add_test(NAME cli.error_tuning_missing COMMAND ${EXPECT_ERROR} "cannot read tuning database .*no-such-tuning.json" env
         SPLATCL_TUNING=${CMAKE_CURRENT_BINARY_DIR}/no-such-tuning.json $<TARGET_FILE:splatcl> cluster --size 64x48)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/tuning-refused.json "{\"records\": [{\"kernel\": \"compact\", \"shape\": \"cpu\", \"parameters\": {\"chunks_per_compute_unit\": 0}}, {\"kernel\": \"radix-sort\", \"shape\": \"cpu\", \"parameters\": {\"digit_bits\": 16}}]}\n")
add_test(NAME cli.error_tuning_refused COMMAND ${EXPECT_ERROR} "tuning-refused.json: records\\[0\\] \\(compact, cpu\\): tuning of compact: chunks_per_compute_unit = 0 is outside 1 .. 256$"
         env SPLATCL_TUNING=${CMAKE_CURRENT_BINARY_DIR}/tuning-refused.json $<TARGET_FILE:splatcl> cluster --size 64x48 --device cpu)
# A record for another device or an unknown kernel: loaded unchecked, and `bench tune -o` wrote it back.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/tuning-other-device.json "{\"records\": [{\"kernel\": \"fft\", \"shape\": \"cpu\", \"device\": {\"vendor\": \"Nobody\"}, \"parameters\": {}}]}\n")
add_test(NAME cli.error_tuning_unknown_kernel COMMAND ${EXPECT_ERROR} "tuning-other-device.json: records\\[0\\] \\(fft, cpu\\): unknown kernel"
         env SPLATCL_TUNING=${CMAKE_CURRENT_BINARY_DIR}/tuning-other-device.json $<TARGET_FILE:splatcl> cluster --size 64x48 --device cpu)
add_test(NAME cli.error_bench_tune_merges_bad_database COMMAND ${EXPECT_ERROR} "tuning-other-device.json: records\\[0\\] \\(fft, cpu\\): unknown kernel"
         $<TARGET_FILE:splatcl> bench tune --quick --kernel scan --shape cpu -o ${CMAKE_CURRENT_BINARY_DIR}/tuning-other-device.json)
# Progress in a log too (only a terminal got it): a line per candidate at SPLATCL_PROGRESS_SECONDS=0.
add_test(NAME cli.bench_tune_progress_in_a_log COMMAND ${EXPECT_OUTPUT} --match "^splatcl bench tune: scan \\(cpu shape\\) on .*: chunks_per_compute_unit="
         -- env SPLATCL_PROGRESS_SECONDS=0 $<TARGET_FILE:splatcl> bench tune --quick --kernel scan --shape cpu -o ${CMAKE_CURRENT_BINARY_DIR}/tune-progress.json)

# scripts/gpu-check.sh without a GPU: refusals without an NVIDIA ICD, and a dry run on PoCL
# (tests/cli/gpu_check_test.sh). Not in the sanitizer pass: a shell script drives the Release binary's steps.
if(NOT SPLATCL_SANITIZE)
  add_test(NAME cli.gpu_check COMMAND ${NEEDS_FILE} ${BENCH_MODEL} ${CMAKE_CURRENT_SOURCE_DIR}/cli/gpu_check_test.sh
           ${PROJECT_SOURCE_DIR}/scripts/gpu-check.sh ${PROJECT_BINARY_DIR} ${CMAKE_CURRENT_BINARY_DIR}/gpu-check)
  set_tests_properties(cli.gpu_check PROPERTIES SKIP_RETURN_CODE 77)
endif()
# --threshold nan: refused before any run (CLI::Range let it through; --compare refused it after the run).
add_test(NAME cli.error_bench_threshold_nan COMMAND ${EXPECT_ERROR} "--threshold: a percentage 0 to 1000000, not nan"
         $<TARGET_FILE:splatcl> bench --threshold nan --quick primitives)
add_test(NAME cli.error_bench_compare_threshold_nan COMMAND ${EXPECT_ERROR} "--threshold: a percentage 0 to 1000000, not nan"
         $<TARGET_FILE:splatcl> bench compare missing.json missing.json --threshold nan)
# Progress in a log (stderr not a terminal): plain lines, as every other command writes (bench wrote none).
add_test(NAME cli.bench_progress_lines_in_a_log COMMAND ${EXPECT_OUTPUT} --match "^splatcl bench primitives: .* median$"
         -- env SPLATCL_PROGRESS_SECONDS=0 $<TARGET_FILE:splatcl> bench primitives --quick --runs 1 --warmup 0)
# --scaling size with more steps than a case has sizes: the repeated smallest size is one row, so
# a results file compared with itself shows no change (6 duplicate rows of the cluster suite did).
set(BENCH_STEPS ${CMAKE_CURRENT_BINARY_DIR}/bench-cluster-steps.json)
add_test(NAME cli.bench_size_steps_write_each_row_once COMMAND $<TARGET_FILE:splatcl> bench cluster --quick --runs 1 --warmup 0
         --scaling size --steps 8 --device cpu --json ${BENCH_STEPS})
set_tests_properties(cli.bench_size_steps_write_each_row_once PROPERTIES FIXTURES_SETUP bench_steps)
add_test(NAME cli.bench_size_steps_compare_identical COMMAND ${EXPECT_OUTPUT} --match "^0 of [1-9][0-9]* matched records regressed by more than 0 %"
         -- $<TARGET_FILE:splatcl> bench compare ${BENCH_STEPS} ${BENCH_STEPS} --threshold 0)
set_tests_properties(cli.bench_size_steps_compare_identical PROPERTIES FIXTURES_REQUIRED bench_steps)
# Options given before and after the suite's name (the suite's won silently), and options that
# only mean something beside another.
add_test(NAME cli.error_bench_option_on_both_levels COMMAND ${EXPECT_ERROR} "--runs is given both before and after the suite's name: give it once"
         $<TARGET_FILE:splatcl> bench --runs 1 primitives --runs 2)
add_test(NAME cli.error_bench_threshold_without_compare COMMAND ${EXPECT_ERROR} "--threshold is the regression threshold of --compare"
         $<TARGET_FILE:splatcl> bench primitives --threshold 5)
add_test(NAME cli.error_bench_steps_without_scaling COMMAND ${EXPECT_ERROR} "--steps counts the sizes of --scaling size"
         $<TARGET_FILE:splatcl> bench primitives --steps 3)
# A results file holding one row twice is refused (report and compare took the first silently).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/bench-twice.json "{\"machine\": {}, \"records\": [{${BENCH_RECORD}, \"median_ms\": 10, \"min_ms\": 9, \"max_ms\": 11}, {${BENCH_RECORD}, \"median_ms\": 1, \"min_ms\": 1, \"max_ms\": 1}]}\n")
add_test(NAME cli.error_bench_record_twice COMMAND ${EXPECT_ERROR} "bench-twice.json: records 0 and 1 are the same row \\(csm/capture/opencl/dev/1000 rays\\)$"
         $<TARGET_FILE:splatcl> bench compare ${CMAKE_CURRENT_BINARY_DIR}/bench-twice.json ${CMAKE_CURRENT_BINARY_DIR}/bench-fast.json)
# Runs measured differently are compared, with a note for each difference (a --warmup 0 run read
# as plain regressions).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/bench-warmup0.json "{\"machine\": {\"warmup\": 0}, \"records\": [{${BENCH_RECORD}, \"median_ms\": 10, \"min_ms\": 9, \"max_ms\": 11}]}\n")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/bench-warmup1.json "{\"machine\": {\"warmup\": 1}, \"records\": [{${BENCH_RECORD}, \"median_ms\": 10, \"min_ms\": 9, \"max_ms\": 11}]}\n")
add_test(NAME cli.bench_compare_notes_other_settings COMMAND ${EXPECT_OUTPUT} --match "^note: the runs differ in warmup: 1 in the baseline, 0 here$"
         -- $<TARGET_FILE:splatcl> bench compare ${CMAKE_CURRENT_BINARY_DIR}/bench-warmup0.json ${CMAKE_CURRENT_BINARY_DIR}/bench-warmup1.json)
# A model that is there but cannot be read fails before any suite runs (it failed the splats suite
# after the others had run, their results lost).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/bench-empty-models/stanford-bunny.obj "")
add_test(NAME cli.error_bench_unreadable_model COMMAND ${EXPECT_ERROR} "cannot read mesh .*bench-empty-models/stanford-bunny.obj: no vertex or face lines"
         $<TARGET_FILE:splatcl> bench --quick --models ${CMAKE_CURRENT_BINARY_DIR}/bench-empty-models)
# Records under the other format's name read back as broken (bench report on JSON named .csv).
add_test(NAME cli.error_bench_json_named_csv COMMAND ${EXPECT_ERROR} "--json .*x.csv: the file must end in .json \\(benchmark records, JSON\\)$"
         $<TARGET_FILE:splatcl> bench primitives --quick --json ${CMAKE_CURRENT_BINARY_DIR}/x.csv)
