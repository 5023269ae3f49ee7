//! A PostgreSQL URL as messages show it: its password hidden. Every build has it, with or
//! without the PostgreSQL store (the `postgres` feature), since a location is shown in
//! every message about it, including that this build cannot open it.

/// `url` with its password, if any, replaced by `***`: the one in the user part
/// (`user:password@`) and every `password` parameter of the query (`?password=...`, the
/// key spelled in any case or percent-encoded, as the `postgres` crate would read it).
pub fn without_password(url: &str) -> String {
    let Some(start) = url.find("://").map(|i| i + 3) else {
        return url.to_owned();
    };
    let (url, query) = match url.find('?') {
        Some(q) if q >= start => (&url[..q], Some(&url[q + 1..])),
        _ => (url, None),
    };
    let mut shown = match url[start..].find('@').map(|i| start + i) {
        Some(at) => match url[start..at].find(':') {
            Some(colon) => format!("{}:***{}", &url[..start + colon], &url[at..]),
            None => url.to_owned(),
        },
        None => url.to_owned(),
    };
    if let Some(query) = query {
        let parameters: Vec<String> = query
            .split('&')
            .map(|p| match p.split_once('=') {
                Some((key, _)) if percent_decoded(key).eq_ignore_ascii_case("password") => {
                    format!("{key}=***")
                }
                _ => p.to_owned(),
            })
            .collect();
        shown = format!("{shown}?{}", parameters.join("&"));
    }
    shown
}

/// `text` with its `%XX` escapes decoded (bytes that do not form UTF-8 are replaced).
fn percent_decoded(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(byte)) => {
                decoded.push(byte);
                i += 3;
            }
            (byte, _) => {
                decoded.push(byte);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&decoded).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passwords_are_not_shown() {
        assert_eq!(
            without_password("postgres://robot:s3cret@fleet.example/cases"),
            "postgres://robot:***@fleet.example/cases"
        );
        assert_eq!(
            without_password("postgres://robot@localhost/cases"),
            "postgres://robot@localhost/cases"
        );
        assert_eq!(
            without_password("postgresql:///cases"),
            "postgresql:///cases"
        );
        assert_eq!(
            without_password(
                "postgres://fleet/cases?user=robot&password=s3cret&application_name=r7"
            ),
            "postgres://fleet/cases?user=robot&password=***&application_name=r7"
        );
        assert_eq!(
            without_password("postgres://a:b@fleet/cases?PASS%77ord=s3cret"),
            "postgres://a:***@fleet/cases?PASS%77ord=***"
        );
    }
}
