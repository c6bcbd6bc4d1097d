#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "controller/trajectory_tracker.h"
#include "mapping/traversability_mapper.h"
#include "planner/navigation_planner.h"
#include "scenarios/run/scenario.h"

namespace trav::scenarios {

/// Makes the mapper of `mapping.method` for a scenario (its `mapping` keys at hand); null means
/// the robot plans on the ground truth (the oracle).
using MapperFactory =
    std::function<std::unique_ptr<mapping::TraversabilityMapper>(const Scenario& scenario)>;

/// Makes the path search of `planner.method` for a scenario (its `planner` keys at hand).
using PathSearchFactory = std::function<planner::PathSearch(const Scenario& scenario)>;

/// Makes the tracker of `controller.method` for a scenario: in mode navigate it tracks the plans,
/// in mode track the scenario's reference (set after it is made).
using ControllerFactory =
    std::function<std::unique_ptr<controller::TrajectoryTracker>(const Scenario& scenario)>;

/// Adds a mapper under `name`, a value of `mapping.method` from then on: a user's program links
/// trav's libraries, registers its mapper and runs scenarios that name it (examples/plugin_mapper)
/// without a change to trav. Built in: fsgp-bgk, fsgp, fsgp-accumulation, sgp, em, ground-truth.
/// @throws std::invalid_argument if `name` is taken, empty, or holds characters other than
/// lower-case letters, digits, '-' and '_'.
void RegisterMapper(const std::string& name, MapperFactory factory);

/// Adds a path search under `name`, a value of `planner.method` from then on. Built in: astar,
/// rrt_star, bit_star, rrt_connect (OMPL, `planner.sampling_iterations` iterations per query).
/// @throws std::invalid_argument as RegisterMapper.
void RegisterPathSearch(const std::string& name, PathSearchFactory factory);

/// Adds a controller under `name`, a value of `controller.method` from then on. Built in: mpc.
/// @throws std::invalid_argument as RegisterMapper.
void RegisterController(const std::string& name, ControllerFactory factory);

/// Every value `mapping.method`, `planner.method` and `controller.method` take now, sorted.
std::vector<std::string> MapperNames();
std::vector<std::string> PathSearchNames();
std::vector<std::string> ControllerNames();

/// The factory registered under `name`. @throws common::InputError naming the key
/// (`mapping.method`, `planner.method`) and the value, and listing the names there are.
const MapperFactory& FindMapper(const std::string& name);
const PathSearchFactory& FindPathSearch(const std::string& name);
const ControllerFactory& FindController(const std::string& name);

}  // namespace trav::scenarios
