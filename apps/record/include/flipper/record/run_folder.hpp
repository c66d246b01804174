#pragma once
/// @file run_folder.hpp
/// Run folders (docs/experiments.md §1): every run writes a new folder and never overwrites one.
/// `--out PARENT` names the parent; the run goes into `PARENT/<stem>-<UTC YYYYMMDD-HHMMSS>`
/// (`-2`, `-3`, ... when that exists: the folder is created atomically, so two processes never
/// share one), and `PARENT/latest` is a link to the last run whose manifest is final (complete,
/// partial or failed): a run moves it when it has written its final manifest, never before, so
/// `latest` never points at a run that is still running or that died.

#include <string>

namespace flipper::record {

/// Creates a fresh run folder under `parent` (created when missing). `stem` is a readable name
/// (the experiment file's name); characters other than letters, digits, '.', '_', '-', '+' and
/// '=' become '_'. Throws sdk::Error(bad_request) when `parent` is itself a run folder (it has a
/// manifest.json) or cannot be created. Returns the new folder's path (`parent`/name).
std::string create_run_folder(const std::string& parent, const std::string& stem);

/// Points the `latest` link beside `run_dir` at it (call after its final manifest is written).
/// A user's own folder called `latest` is left alone.
void mark_latest(const std::string& run_dir);

/// Whether `dir` is a run folder (holds manifest.json).
bool is_run_folder(const std::string& dir);

/// A directory name from a readable name: letters, digits, '.', '_', '-', '+', '=' kept, ','
/// (between a sweep point's settings) '+', every other character '_'; names longer than 120
/// characters keep their first 100 and add the first 12 hex digits of the name's SHA-256, so
/// distinct long names stay distinct.
std::string directory_name(const std::string& name);

/// The current time in UTC as ISO 8601 ("2025-01-31T12:00:00Z").
std::string utc_now();

}  // namespace flipper::record
