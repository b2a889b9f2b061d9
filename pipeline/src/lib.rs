//! squeal-pipeline: scenes, stage orchestration, outputs.
