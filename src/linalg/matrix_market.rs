//! Matrix Market reading and writing (placeholder, being written).
