#pragma once

#include <string_view>

namespace trav::lidar {

/// The text of the shipped head of Livox's MID-360 scan table (50,157 rows of
/// `Time/s,Azimuth/deg,Zenith/deg`; sim/lidar/data/livox_mid360, MIT licence), compiled into the
/// library so that the default pattern needs no file at run time.
std::string_view Mid360TableText();

}  // namespace trav::lidar
