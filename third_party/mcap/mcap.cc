// The MCAP library's implementation (reader and writer), compiled once for trav::mcap.
#define MCAP_IMPLEMENTATION
#include <mcap/mcap.hpp>
