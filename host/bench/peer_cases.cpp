#include "bench/peer_cases.hpp"

#include <algorithm>

#ifdef SPLATCL_HAVE_BOOST_COMPUTE
#include "bench/peers/boost_compute.hpp"
#endif

namespace splatcl::bench {

void measure_sort_peers(Session& session, Case c, PeerWork work, const std::vector<std::uint32_t>& keys,
                        const std::vector<std::uint32_t>& expected) {
  const bool with_sort = work != PeerWork::Unique;
  const bool with_unique = work != PeerWork::Sort;

  std::vector<std::uint32_t> host_keys;
  std::size_t count = 0;
  c.impl = kImplStd;
  c.on_device = false;
  session.measure(c, [&] { host_keys = keys; }, [&] {
    if (with_sort) std::sort(host_keys.begin(), host_keys.end());
    count = with_unique ? static_cast<std::size_t>(std::unique(host_keys.begin(), host_keys.end()) - host_keys.begin())
                        : host_keys.size();
  });
  host_keys.resize(count);
  expect_same_output(describe(c), host_keys, expected);

#ifdef SPLATCL_HAVE_BOOST_COMPUTE
  BoostComputePeer boost_compute(session.runtime().info().name);
  boost_compute.load(keys);
  c.impl = kImplBoostCompute;
  c.on_device = true;
  session.measure(c, [&] { boost_compute.reset(); }, [&] {
    if (with_sort) boost_compute.sort();
    count = with_unique ? boost_compute.unique() : keys.size();
  });
  // Boost.Compute's unique is wrong on PoCL with one thread (POCL_MAX_PTHREAD_COUNT=1, as
  // --scaling threads runs it): a peer's bug must not cost the run every other result.
  try {
    expect_same_output(describe(c), boost_compute.download(count), expected);
  } catch (const Error& wrong) {
    session.withdraw_last_record(wrong.what());
  }
#endif
}

}  // namespace splatcl::bench
