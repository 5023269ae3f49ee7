//! Reading newline-terminated lines with a length limit.
//!
//! A line longer than the limit is consumed and discarded up to its newline without being
//! kept in memory, so a hostile or broken peer can neither exhaust memory nor desynchronise
//! the conversation: the next line is read normally.

use std::io::{self, BufRead};

/// What [`read_line`] found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineRead {
    /// A line (without its `\n` or `\r\n`) is in the buffer.
    Line,
    /// A line longer than the limit was read and discarded; the buffer is empty.
    TooLong,
}

/// Reads the next line into `line` (cleared first). The last line may lack its newline.
/// Returns `None` at the end of the input.
pub fn read_line<R: BufRead + ?Sized>(
    reader: &mut R,
    limit: usize,
    line: &mut Vec<u8>,
) -> io::Result<Option<LineRead>> {
    line.clear();
    let mut read_any = false;
    let mut too_long = false;
    loop {
        let available = match reader.fill_buf() {
            Ok(bytes) => bytes,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if available.is_empty() {
            return Ok(read_any.then_some(finish(line, limit, too_long)));
        }
        read_any = true;
        let newline = available.iter().position(|&b| b == b'\n');
        let chunk = &available[..newline.unwrap_or(available.len())];
        if !too_long {
            // One byte more than the limit may be a `\r` before the newline.
            if line.len() + chunk.len() > limit + 1 {
                too_long = true;
                line.clear();
            } else {
                line.extend_from_slice(chunk);
            }
        }
        let used = chunk.len() + usize::from(newline.is_some());
        reader.consume(used);
        if newline.is_some() {
            return Ok(Some(finish(line, limit, too_long)));
        }
    }
}

/// The limit excludes the line terminator, `\n` or `\r\n`.
fn finish(line: &mut Vec<u8>, limit: usize, too_long: bool) -> LineRead {
    if line.last() == Some(&b'\r') {
        line.pop();
    }
    if too_long || line.len() > limit {
        line.clear();
        LineRead::TooLong
    } else {
        LineRead::Line
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::BufReader;

    fn all_lines(input: &[u8], limit: usize, capacity: usize) -> Vec<Result<String, ()>> {
        let mut reader = BufReader::with_capacity(capacity, input);
        let mut line = Vec::new();
        let mut out = Vec::new();
        while let Some(read) = read_line(&mut reader, limit, &mut line).unwrap() {
            out.push(match read {
                LineRead::Line => Ok(String::from_utf8(line.clone()).unwrap()),
                LineRead::TooLong => Err(()),
            });
        }
        out
    }

    #[test]
    fn lines_are_split_and_crlf_trimmed() {
        let got = all_lines(b"ab\r\n\ncd", 10, 3);
        assert_eq!(
            got,
            vec![Ok("ab".into()), Ok(String::new()), Ok("cd".into())]
        );
    }

    #[test]
    fn an_oversize_line_is_skipped_and_the_next_is_read() {
        // The limit is 4 bytes; the buffer is smaller than the long line, so it arrives in
        // pieces and is dropped piece by piece.
        let got = all_lines(b"0123456789\nok\n12345", 4, 3);
        assert_eq!(got, vec![Err(()), Ok("ok".into()), Err(())]);
        assert_eq!(all_lines(b"1234\n", 4, 2), vec![Ok("1234".into())]);
    }

    #[test]
    fn the_limit_excludes_a_crlf_terminator() {
        let lines = |input: &[u8]| all_lines(input, 4, 2);
        assert_eq!(
            lines(b"1234\r\nok\r\n"),
            vec![Ok("1234".into()), Ok("ok".into())]
        );
        assert_eq!(lines(b"1234\r"), vec![Ok("1234".into())]);
        assert_eq!(lines(b"12345\r\nok\n"), vec![Err(()), Ok("ok".into())]);
        assert_eq!(lines(b"1234\r5\n"), vec![Err(())]);
    }

    #[test]
    fn empty_input_has_no_lines() {
        assert!(all_lines(b"", 4, 2).is_empty());
    }
}
