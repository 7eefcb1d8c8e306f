//! The repository as a whole: the docs a student reads, the layers of the source, its words.

mod docs;
mod layers;
mod own_words;
mod walkthrough;
