//! A small command-line parser: positional arguments, `--flag value`
//! options and `--switch`es, each command declaring which it accepts.

use super::AppError;
use std::collections::BTreeMap;
use std::str::FromStr;

/// The parsed arguments of one command.
#[derive(Debug, Default)]
pub struct Args {
    positional: Vec<String>,
    options: BTreeMap<String, String>,
    switches: Vec<String>,
}

impl Args {
    /// Parses `args`, where `options` take a value and `switches` do not.
    ///
    /// # Errors
    /// A usage error for an unknown `--name`, an option without its value,
    /// or an option given twice.
    pub fn parse(args: &[String], options: &[&str], switches: &[&str]) -> Result<Args, AppError> {
        let mut parsed = Args::default();
        let mut iter = args.iter();
        while let Some(arg) = iter.next() {
            let Some(name) = arg.strip_prefix("--") else {
                parsed.positional.push(arg.clone());
                continue;
            };
            if switches.contains(&name) {
                parsed.switches.push(name.to_string());
            } else if options.contains(&name) {
                let value = iter
                    .next()
                    .ok_or_else(|| AppError::Usage(format!("--{name} needs a value")))?;
                if parsed
                    .options
                    .insert(name.to_string(), value.clone())
                    .is_some()
                {
                    return Err(AppError::Usage(format!("--{name} given twice")));
                }
            } else {
                return Err(AppError::Usage(format!("unknown option '{arg}'")));
            }
        }
        Ok(parsed)
    }

    /// The single positional argument, named `what` in errors.
    ///
    /// # Errors
    /// A usage error when there is not exactly one.
    pub fn single_positional(&self, what: &str) -> Result<&str, AppError> {
        match self.positional.as_slice() {
            [one] => Ok(one),
            [] => Err(AppError::Usage(format!("missing {what}"))),
            [_, extra, ..] => Err(AppError::Usage(format!("unexpected argument '{extra}'"))),
        }
    }

    /// The positional arguments, in order.
    pub fn positional(&self) -> &[String] {
        &self.positional
    }

    /// Was `--name` given?
    pub fn switch(&self, name: &str) -> bool {
        self.switches.iter().any(|s| s == name)
    }

    /// The value of `--name` parsed as `T`, or `default` when absent.
    ///
    /// # Errors
    /// A usage error naming the option when the value does not parse.
    pub fn value_or<T: FromStr>(&self, name: &str, default: T) -> Result<T, AppError>
    where
        T::Err: std::fmt::Display,
    {
        match self.options.get(name) {
            None => Ok(default),
            Some(text) => text
                .parse()
                .map_err(|e| AppError::Usage(format!("--{name} {text}: {e}"))),
        }
    }
}
