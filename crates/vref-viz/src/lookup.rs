use vref_scene::{DatasetError, ScenePair};

use crate::SceneLookupError;

/// Scene names an unknown-scene error shows.
const EXAMPLES: usize = 5;

/// The first scene called `name` among `scenes` (a `DatasetReader`, say).
/// Reading stops there, so a bad line after it goes unnoticed; a bad line
/// before it is an error, as `vref eval` would report it.
pub fn find_scene<I>(scenes: I, name: &str) -> Result<ScenePair, SceneLookupError>
where
    I: IntoIterator<Item = Result<ScenePair, DatasetError>>,
{
    let mut names = Vec::new();
    for pair in scenes {
        let pair = pair?;
        if pair.name == name {
            return Ok(pair);
        }
        names.push(pair.name);
    }
    Err(SceneLookupError::UnknownScene {
        name: name.to_owned(),
        total: names.len(),
        examples: examples(names, name),
    })
}

/// A few names worth showing: those containing what was asked for (a typo
/// or a prefix such as `house1` is the usual mistake), then the first ones.
fn examples(names: Vec<String>, asked: &str) -> Vec<String> {
    let asked = asked.to_lowercase();
    let (mut close, rest): (Vec<String>, Vec<String>) = names
        .into_iter()
        .partition(|n| !asked.is_empty() && n.to_lowercase().contains(&asked));
    close.extend(rest);
    close.truncate(EXAMPLES);
    close
}
