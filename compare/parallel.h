// Independent pieces of work spread over the cores: the outputs a diff measures, the pictures a
// report draws.
#pragma once

#include <cstddef>
#include <functional>

namespace nightcap {

// Runs work(i) for every i in [0, count) on a worker per core (at most `count`), each taking the
// next index. After the first exception no further index is started; that exception is rethrown
// once every worker has stopped.
void for_each_on_cores(size_t count, const std::function<void(size_t)>& work);

}  // namespace nightcap
