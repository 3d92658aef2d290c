//! `--parameter NAME=VALUE` (`-p`): the command line's values for a model file's `[parameters]`,
//! applied as a study's variants and `flexmb.load(parameters=…)` apply theirs
//! ([`ModelOverrides`](flexmb_files::model_file::ModelOverrides)).

use flexmb_files::model_file::LoadOptions;

/// Parses `NAME=VALUE`, VALUE a finite number.
pub fn parse_parameter(text: &str) -> Result<(String, f64), String> {
    let Some((name, value)) = text.split_once('=') else {
        return Err(format!("expected NAME=VALUE (e.g. L=2.5), got `{text}`"));
    };
    let name = name.trim();
    if name.is_empty() {
        return Err(format!("expected NAME=VALUE (e.g. L=2.5), got `{text}`: the name is empty"));
    }
    match value.trim().parse::<f64>() {
        Ok(number) if number.is_finite() => Ok((name.to_string(), number)),
        _ => Err(format!("the value of `{name}` must be a finite number, got `{}`", value.trim())),
    }
}

/// How the commands load a model file with `parameters` replacing values of its `[parameters]`
/// (a later value of the same name wins): [`load_options`](crate::limits::load_options) with them.
pub fn load_options_with(parameters: &[(String, f64)]) -> LoadOptions {
    let mut options = crate::limits::load_options();
    options.overrides.parameters = parameters.to_vec();
    options
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_values() {
        assert_eq!(parse_parameter("L=2.5"), Ok(("L".to_string(), 2.5)));
        assert_eq!(parse_parameter(" m_bob = 1e-3 "), Ok(("m_bob".to_string(), 1e-3)));
        assert!(parse_parameter("L").unwrap_err().contains("expected NAME=VALUE"));
        assert!(parse_parameter("=2").unwrap_err().contains("the name is empty"));
        assert!(parse_parameter("L=two").unwrap_err().contains("must be a finite number, got `two`"));
        assert!(parse_parameter("L=inf").unwrap_err().contains("finite"));
    }
}
