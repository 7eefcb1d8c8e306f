//! The command line, table-driven: each command declares its operands and
//! its flags once, in its own file, as a [`CommandSpec`]; the same table
//! parses the arguments ([`Args::parse`]) and writes the help
//! ([`CommandSpec::help`], and the list of commands in `masssprings help`),
//! so the usage text cannot drift from what is accepted.
//!
//! Errors are plain words naming the flag and what it expects
//! ("--steps expects a whole number ≥ 0, got 'ten'"), with a "did you
//! mean" for a mistyped flag ([`super::suggest`]).

use super::suggest::nearest;
use super::AppError;
use std::collections::BTreeMap;
use std::ops::RangeInclusive;
use std::str::FromStr;

/// One flag of a command: `--name VALUE` or a `--name` switch.
#[derive(Debug)]
pub struct Flag {
    pub name: &'static str,
    /// The value's placeholder in the help (`N`, `DIR`); `None` for a switch.
    pub value: Option<&'static str>,
    /// One line for the help.
    pub help: &'static str,
}

impl Flag {
    /// `--name VALUE`.
    pub const fn value(name: &'static str, value: &'static str, help: &'static str) -> Flag {
        Flag {
            name,
            value: Some(value),
            help,
        }
    }

    /// `--name`, on or off.
    pub const fn switch(name: &'static str, help: &'static str) -> Flag {
        Flag {
            name,
            value: None,
            help,
        }
    }
}

/// A command: its name, operands, what it does, its flags, and the
/// function that runs it.
#[derive(Debug)]
pub struct CommandSpec {
    pub name: &'static str,
    /// The operands as the usage line shows them (`SCENE.json`).
    pub operands: &'static str,
    /// One line for the list of commands.
    pub summary: &'static str,
    /// Paragraphs for the command's own help (already wrapped).
    pub details: &'static str,
    pub flags: &'static [Flag],
    /// One-letter short forms: (`'o'`, `"out"`) makes `-o` mean `--out`.
    pub shorts: &'static [(char, &'static str)],
    pub run: fn(&[String]) -> Result<(), AppError>,
}

/// Column where the flags' help starts.
const HELP_COLUMN: usize = 24;
/// Width the help is wrapped to.
const HELP_WIDTH: usize = 79;

impl CommandSpec {
    /// `masssprings NAME OPERANDS [options]`.
    pub fn usage(&self) -> String {
        let options = if self.flags.is_empty() {
            ""
        } else {
            " [options]"
        };
        format!("masssprings {} {}{options}", self.name, self.operands)
    }

    /// The full help of the command, from the table.
    pub fn help(&self) -> String {
        let mut text = format!("usage: {}\n\n{}\n", self.usage(), self.details.trim_end());
        text.push_str("\noptions:\n");
        for flag in self.flags {
            let short = self
                .shorts
                .iter()
                .find(|(_, long)| *long == flag.name)
                .map(|(c, _)| format!("-{c}, "))
                .unwrap_or_default();
            let value = flag.value.map(|v| format!(" {v}")).unwrap_or_default();
            push_entry(
                &mut text,
                &format!("{short}--{}{value}", flag.name),
                flag.help,
            );
        }
        push_entry(&mut text, "-h, --help", "This help.");
        text
    }

    fn flag(&self, name: &str) -> Option<&Flag> {
        self.flags.iter().find(|flag| flag.name == name)
    }
}

/// `  left   help…`, the help wrapped at [`HELP_WIDTH`] and indented to
/// [`HELP_COLUMN`] (on the next line when `left` is too long).
pub fn push_entry(text: &mut String, left: &str, help: &str) {
    let mut line = format!("  {left}");
    if line.chars().count() + 2 > HELP_COLUMN {
        text.push_str(&line);
        text.push('\n');
        line = String::new();
    }
    for word in help.split_whitespace() {
        let width = line.chars().count();
        let fresh = width <= HELP_COLUMN;
        if !fresh && width + 1 + word.chars().count() > HELP_WIDTH {
            text.push_str(&line);
            text.push('\n');
            line = String::new();
        }
        let width = line.chars().count();
        if width < HELP_COLUMN {
            line.push_str(&" ".repeat(HELP_COLUMN - width));
        } else {
            line.push(' ');
        }
        line.push_str(word);
    }
    text.push_str(&line);
    text.push('\n');
}

/// The parsed arguments of one command.
#[derive(Debug)]
pub struct Args {
    command: &'static CommandSpec,
    positional: Vec<String>,
    options: BTreeMap<&'static str, String>,
    switches: Vec<&'static str>,
}

impl Args {
    /// Parses `args` against `command`'s flags. Accepts `--name value`,
    /// `--name=value`, the short forms, and `--` (everything after it is an
    /// operand).
    ///
    /// # Errors
    /// A usage error for an unknown flag (with the nearest known one), a
    /// flag without its value, a value given to a switch, or a flag given
    /// twice.
    pub fn parse(args: &[String], command: &'static CommandSpec) -> Result<Args, AppError> {
        let mut parsed = Args {
            command,
            positional: Vec::new(),
            options: BTreeMap::new(),
            switches: Vec::new(),
        };
        let mut iter = args.iter();
        while let Some(arg) = iter.next() {
            if arg == "--" {
                parsed.positional.extend(iter.by_ref().cloned());
                break;
            }
            let Some((name, inline_value)) = parsed.flag_name(arg)? else {
                parsed.positional.push(arg.clone());
                continue;
            };
            let flag = command.flag(name).expect("flag_name checks it");
            match (flag.value, inline_value) {
                (None, None) => {
                    if parsed.switches.contains(&flag.name) {
                        return Err(AppError::Usage(format!("--{name} given twice")));
                    }
                    parsed.switches.push(flag.name);
                }
                (None, Some(_)) => {
                    return Err(AppError::Usage(format!("--{name} takes no value")));
                }
                (Some(placeholder), value) => {
                    let value = match value {
                        Some(value) => value,
                        None => iter.next().cloned().ok_or_else(|| {
                            AppError::Usage(format!(
                                "--{name} needs a value: --{name} {placeholder}"
                            ))
                        })?,
                    };
                    if parsed.options.insert(flag.name, value).is_some() {
                        return Err(AppError::Usage(format!("--{name} given twice")));
                    }
                }
            }
        }
        Ok(parsed)
    }

    /// The flag `arg` names and its `=value`, `None` for an operand.
    fn flag_name(&self, arg: &str) -> Result<Option<(&'static str, Option<String>)>, AppError> {
        let spec = self.command;
        let (name, value) = if let Some(long) = arg.strip_prefix("--") {
            match long.split_once('=') {
                Some((name, value)) => (name.to_string(), Some(value.to_string())),
                None => (long.to_string(), None),
            }
        } else if let Some(short) = arg.strip_prefix('-').filter(|s| s.chars().count() == 1) {
            let c = short.chars().next().expect("one character");
            match spec.shorts.iter().find(|(s, _)| *s == c) {
                Some((_, long)) => (long.to_string(), None),
                None => return Err(self.unknown(arg)),
            }
        } else {
            return Ok(None); // an operand (including "-" and negative numbers)
        };
        match spec.flag(&name) {
            Some(flag) => Ok(Some((flag.name, value))),
            None => Err(self.unknown(arg)),
        }
    }

    fn unknown(&self, arg: &str) -> AppError {
        let spec = self.command;
        let word = arg.trim_start_matches('-').split('=').next().unwrap_or("");
        let hint = nearest(word, spec.flags.iter().map(|f| f.name))
            .map(|name| format!("; did you mean --{name}?"))
            .unwrap_or_default();
        AppError::Usage(format!("{} has no option '{arg}'{hint}", spec.name))
    }

    /// The single operand, named `what` in errors.
    ///
    /// # Errors
    /// A usage error when there is not exactly one.
    pub fn single_positional(&self, what: &str) -> Result<&str, AppError> {
        match self.positional.as_slice() {
            [one] => Ok(one),
            [] => Err(AppError::Usage(format!(
                "missing {what}: {}",
                self.command.usage()
            ))),
            [_, extra, ..] => Err(AppError::Usage(format!("unexpected argument '{extra}'"))),
        }
    }

    /// All operands, in order.
    pub fn positionals(&self) -> &[String] {
        &self.positional
    }

    /// Does the command's table have `--name`?
    pub fn declares(&self, name: &str) -> bool {
        self.command.flag(name).is_some()
    }

    /// Was `--name` given?
    pub fn switch(&self, name: &str) -> bool {
        self.check_declared(name);
        self.switches.contains(&name)
    }

    /// The text of `--name`, if given.
    pub fn text(&self, name: &str) -> Option<&str> {
        self.check_declared(name);
        self.options.get(name).map(String::as_str)
    }

    /// `--name` as a whole number within `range`, or `default`.
    ///
    /// # Errors
    /// A usage error in plain words: "--steps expects a whole number ≥ 0,
    /// got 'ten'".
    pub fn whole_number(
        &self,
        name: &str,
        default: u64,
        range: RangeInclusive<u64>,
    ) -> Result<u64, AppError> {
        let Some(text) = self.text(name) else {
            return Ok(default);
        };
        let expects = if *range.end() == u64::MAX {
            format!("a whole number ≥ {}", range.start())
        } else {
            format!("a whole number from {} to {}", range.start(), range.end())
        };
        match text.trim().parse::<u128>() {
            Ok(value) if value <= u128::from(u64::MAX) && range.contains(&(value as u64)) => {
                Ok(value as u64)
            }
            Ok(_) => Err(AppError::Usage(format!(
                "--{name} expects {expects}; {text} is out of range"
            ))),
            Err(_) => Err(AppError::Usage(format!(
                "--{name} expects {expects}, got '{text}'"
            ))),
        }
    }

    /// `--name` as a count (a whole number ≥ `least`), or `default`.
    ///
    /// # Errors
    /// As [`Args::whole_number`].
    pub fn count(&self, name: &str, default: usize, least: usize) -> Result<usize, AppError> {
        let value = self.whole_number(name, default as u64, least as u64..=usize::MAX as u64)?;
        Ok(value as usize)
    }

    /// `--name` as a count of at least `least` when it is given, `None`
    /// when it is not: for a flag whose absence means something else than
    /// any count (so that `--steps 0` is refused instead of being read as
    /// "not given").
    ///
    /// # Errors
    /// As [`Args::whole_number`].
    pub fn optional_count(&self, name: &str, least: usize) -> Result<Option<usize>, AppError> {
        match self.text(name) {
            None => Ok(None),
            Some(_) => self.count(name, least, least).map(Some),
        }
    }

    /// `--name` as a finite number within `range`, or `default` (for
    /// real-valued flags such as `--tolerance`).
    ///
    /// # Errors
    /// A usage error: "--k expects a number from 1 to 1e9, got 'stiff'".
    #[allow(dead_code)] // no command has a real-valued flag yet
    pub fn number(
        &self,
        name: &str,
        default: f64,
        range: RangeInclusive<f64>,
    ) -> Result<f64, AppError> {
        let Some(text) = self.text(name) else {
            return Ok(default);
        };
        match text.trim().parse::<f64>() {
            Ok(value) if value.is_finite() && range.contains(&value) => Ok(value),
            _ => Err(AppError::Usage(format!(
                "--{name} expects a number from {} to {}, got '{text}'",
                range.start(),
                range.end()
            ))),
        }
    }

    /// `--name` as one of `choices`, or `default`.
    ///
    /// # Errors
    /// A usage error listing the choices, with the nearest one.
    pub fn choice(
        &self,
        name: &str,
        default: &'static str,
        choices: &[&'static str],
    ) -> Result<&'static str, AppError> {
        let Some(text) = self.text(name) else {
            return Ok(default);
        };
        if let Some(&choice) = choices.iter().find(|&&c| c == text) {
            return Ok(choice);
        }
        let hint = nearest(text, choices.iter().copied())
            .map(|c| format!("; did you mean {c}?"))
            .unwrap_or_default();
        Err(AppError::Usage(format!(
            "--{name} expects {}, got '{text}'{hint}",
            one_of(choices)
        )))
    }

    /// `--name` parsed as `T`, or `default`; `expects` says what a good
    /// value is, for the error ("an IP address such as 127.0.0.1").
    ///
    /// # Errors
    /// A usage error: "--address expects an IP address …, got 'nowhere'".
    pub fn parsed<T: FromStr>(&self, name: &str, default: T, expects: &str) -> Result<T, AppError> {
        match self.text(name) {
            None => Ok(default),
            Some(text) => text
                .trim()
                .parse()
                .map_err(|_| AppError::Usage(format!("--{name} expects {expects}, got '{text}'"))),
        }
    }

    /// A flag the code asks for must be in the command's table.
    fn check_declared(&self, name: &str) {
        debug_assert!(
            self.command.flag(name).is_some(),
            "{} asks for --{name}, which its table does not declare",
            self.command.name
        );
    }
}

/// `a, b or c`.
pub fn one_of(choices: &[&str]) -> String {
    match choices {
        [] => String::new(),
        [one] => (*one).to_string(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nothing(_: &[String]) -> Result<(), AppError> {
        Ok(())
    }

    static SPEC: CommandSpec = CommandSpec {
        name: "try",
        operands: "FILE",
        summary: "A command for the tests.",
        details: "Does nothing.",
        flags: &[
            Flag::value("steps", "N", "Steps (default 100)."),
            Flag::value("port", "P", "A port."),
            Flag::value("out", "DIR", "Where to write."),
            Flag::value("ordering", "amd|natural", "The ordering."),
            Flag::value("k", "K", "Stiffness."),
            Flag::switch("dense", "Dense matrices."),
        ],
        shorts: &[('o', "out")],
        run: nothing,
    };

    fn parse(args: &[&str]) -> Result<Args, AppError> {
        let args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        Args::parse(&args, &SPEC)
    }

    fn usage_message(result: Result<impl std::fmt::Debug, AppError>) -> String {
        match result {
            Err(AppError::Usage(message)) => message,
            other => panic!("expected a usage error, got {other:?}"),
        }
    }

    #[test]
    fn flags_switches_operands_and_short_forms_parse() {
        let args = parse(&["a.json", "--steps", "7", "--dense", "-o", "x", "--port=9"]).unwrap();
        assert_eq!(args.single_positional("FILE").unwrap(), "a.json");
        assert_eq!(args.count("steps", 100, 0).unwrap(), 7);
        assert!(args.switch("dense"));
        assert_eq!(args.text("out"), Some("x"));
        assert_eq!(args.whole_number("port", 8080, 0..=65535).unwrap(), 9);
        let defaults = parse(&["--", "-weird.json"]).unwrap();
        assert_eq!(defaults.single_positional("FILE").unwrap(), "-weird.json");
        assert_eq!(defaults.count("steps", 100, 0).unwrap(), 100);
        assert!(!defaults.switch("dense"));
    }

    #[test]
    fn an_optional_count_is_none_when_absent_and_refuses_less_than_its_least() {
        let args = parse(&["--steps", "3", "--k", "0"]).unwrap();
        assert_eq!(args.optional_count("steps", 1).unwrap(), Some(3));
        assert_eq!(args.optional_count("port", 1).unwrap(), None);
        let message = usage_message(args.optional_count("k", 1));
        assert_eq!(message, "--k expects a whole number ≥ 1; 0 is out of range");
    }

    #[test]
    fn bad_numbers_are_explained_in_plain_words() {
        let message = usage_message(parse(&["--steps", "ten"]).unwrap().count("steps", 1, 0));
        assert_eq!(message, "--steps expects a whole number ≥ 0, got 'ten'");
        let message = usage_message(parse(&["--port", "99999"]).unwrap().whole_number(
            "port",
            1,
            0..=65535,
        ));
        assert_eq!(
            message,
            "--port expects a whole number from 0 to 65535; 99999 is out of range"
        );
        let huge = "1".repeat(60);
        let message = usage_message(parse(&["--steps", &huge]).unwrap().count("steps", 1, 0));
        assert!(message.contains("a whole number ≥ 0"), "{message}");
        let message = usage_message(parse(&["--k", "nan"]).unwrap().number("k", 1.0, 0.0..=1e9));
        assert_eq!(
            message,
            "--k expects a number from 0 to 1000000000, got 'nan'"
        );
        let message = usage_message(parse(&["--steps", "-1"]).unwrap().count("steps", 1, 0));
        assert!(message.contains("got '-1'"), "{message}");
    }

    #[test]
    fn unknown_flags_and_choices_suggest_the_nearest() {
        let message = usage_message(parse(&["--step", "3"]));
        assert!(
            message.starts_with("try has no option '--step'; did you mean --steps?"),
            "{message}"
        );
        let message = usage_message(parse(&["--frobnicate"]));
        assert!(!message.contains("did you mean"), "{message}");
        let message = usage_message(parse(&["-x"]));
        assert!(message.contains("'-x'"), "{message}");
        let message = usage_message(parse(&["--ordering", "amf"]).unwrap().choice(
            "ordering",
            "amd",
            &["amd", "natural"],
        ));
        assert_eq!(
            message,
            "--ordering expects amd or natural, got 'amf'; did you mean amd?"
        );
    }

    #[test]
    fn missing_repeated_and_misplaced_values_are_usage_errors() {
        assert!(usage_message(parse(&["--steps"])).contains("--steps needs a value"));
        assert!(usage_message(parse(&["--steps", "1", "--steps", "2"])).contains("twice"));
        assert!(usage_message(parse(&["--dense", "--dense"])).contains("twice"));
        assert!(usage_message(parse(&["--dense=yes"])).contains("takes no value"));
        let two = parse(&["a", "b"]).unwrap();
        assert!(usage_message(two.single_positional("FILE")).contains("unexpected argument 'b'"));
        let none = parse(&[]).unwrap();
        assert!(usage_message(none.single_positional("FILE")).contains("missing FILE"));
    }

    #[test]
    fn the_help_lists_every_flag_of_the_table() {
        let help = SPEC.help();
        assert!(help.starts_with("usage: masssprings try FILE [options]\n"));
        for flag in SPEC.flags {
            assert!(help.contains(&format!("--{}", flag.name)), "{help}");
            assert!(help.contains(flag.help), "{help}");
        }
        assert!(help.contains("-o, --out DIR"));
        assert!(help.contains("-h, --help"));
        assert!(
            help.lines().all(|line| line.chars().count() <= HELP_WIDTH),
            "{help}"
        );
    }
}
