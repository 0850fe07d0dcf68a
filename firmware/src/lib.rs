#![doc = include_str!("../README.md")]
#![no_std]
#![warn(missing_docs)]

pub mod app;
pub mod board;
pub mod fault;
pub mod stack;
