// The hidden worker commands trav starts itself: a Slurm array task and one scene of trav eval.
#include <cstdint>
#include <memory>
#include <string>

#include "scenarios/cli/cli.h"
#include "scenarios/experiments/evaluation.h"
#include "scenarios/experiments/job_array.h"

namespace trav::scenarios::cli {

Command AddJobTaskCommand(CLI::App* app) {
  auto task_file = std::make_shared<std::string>();
  auto task_index = std::make_shared<int>(0);
  CLI::App* job_task = app->add_subcommand("job-task", "");
  job_task->group("");
  job_task->add_option("tasks", *task_file)->required();
  job_task->add_option("index", *task_index)->required();
  return {job_task, [task_file, task_index] {
            RunJobTask(*task_file, *task_index);
            return kExitExpected;
          }};
}

Command AddEvalSceneCommand(CLI::App* app) {
  struct SceneFlags {
    std::string folder, terrain;
    std::uint64_t seed{0};
  };
  auto flags = std::make_shared<SceneFlags>();
  CLI::App* eval_scene = app->add_subcommand("eval-scene", "");
  eval_scene->group("");
  eval_scene->add_option("folder", flags->folder)->required();
  eval_scene->add_option("terrain", flags->terrain)->required();
  eval_scene->add_option("seed", flags->seed)->required();
  return {eval_scene, [flags] {
            RunEvalSceneInFolder(flags->folder, {flags->terrain, flags->seed}, ModelsDirectory());
            return kExitExpected;
          }};
}

}  // namespace trav::scenarios::cli
