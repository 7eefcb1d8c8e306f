//! The command line and the viewer, run as a user runs them.

mod cli;
mod command_line;
mod converge_command;
mod cpp_header;
mod diagnosis;
mod output_folders;
mod render;
mod resume;
mod teaching_cli;
mod trace;
mod viewer;
