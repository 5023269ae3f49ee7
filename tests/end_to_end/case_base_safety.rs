//! End-to-end: no `cases` command or `serve` destroys or alters a case base it did not mean
//! to write. An export never writes over its source or over anything but an earlier
//! export; a store refused as foreign or corrupt is left byte for byte as it was (and gets
//! no `-wal` or `-shm` beside it); `cases info` and `cases export` only read; no password
//! is ever shown. The PostgreSQL tests use the server named by `TRUSTCBR_TEST_POSTGRES`
//! (`.ci/run` starts one) and are skipped with a message without it, except under CI.

use crate::support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use support::{succeed, trustcbr};

/// Runs `command` with no input, checks that it failed with an error (status 1) rather than
/// a panic, and returns its stderr.
fn refused(command: &mut Command) -> String {
    let output: Output = command.stdin(Stdio::null()).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    stderr
}

/// A folder holding the quick domain and a case base of three cases, `base.db`.
struct Bases {
    dir: tempfile::TempDir,
}

impl Bases {
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("quick.ron"), support::quick_domain(false)).unwrap();
        std::fs::write(
            dir.path().join("three.ron"),
            "(cases: [
                (problem: [(behavior: [0, 0], time: 1.0)], solution: [1, 1]),
                (problem: [(behavior: [1, 1], time: 2.0)], solution: [2, 2]),
                (problem: [(behavior: [2, 2], time: 3.0)], solution: [3, 3]),
            ])",
        )
        .unwrap();
        let bases = Self { dir };
        bases.import(bases.path("base.db").to_str().unwrap());
        bases
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// `cases import three.ron TARGET --domain quick.ron`, which must succeed.
    fn import(&self, target: &str) {
        succeed(&mut self.import_command(target));
    }

    /// `cases import three.ron TARGET --domain quick.ron`.
    fn import_command(&self, target: &str) -> Command {
        let mut command = trustcbr();
        command
            .args(["cases", "import"])
            .arg(self.path("three.ron"))
            .arg(target)
            .arg("--domain")
            .arg(self.domain());
        command
    }

    /// `serve --domain quick.ron --cases CASES`.
    fn serve_command(&self, cases: &str) -> Command {
        let mut command = trustcbr();
        command
            .args(["serve", "--domain"])
            .arg(self.domain())
            .args(["--cases", cases]);
        command
    }

    fn domain(&self) -> PathBuf {
        self.path("quick.ron")
    }
}

/// A hash of the bytes of `path` and of its `-wal` and `-shm` siblings (absent: `None`).
fn snapshot(path: &Path) -> [Option<u64>; 3] {
    use std::hash::{DefaultHasher, Hash, Hasher};
    ["", "-wal", "-shm"].map(|suffix| {
        let mut name = path.as_os_str().to_owned();
        name.push(suffix);
        std::fs::read(PathBuf::from(name)).ok().map(|bytes| {
            let mut hasher = DefaultHasher::new();
            bytes.hash(&mut hasher);
            hasher.finish()
        })
    })
}

/// Whether the case base at `path` is as `before` (a [`snapshot`]) left it: the same bytes,
/// and no `-wal` holding anything (a reader of a database in WAL mode may leave an empty
/// `-wal` and a `-shm` index beside it).
fn unchanged(path: &Path, before: &[Option<u64>; 3]) -> bool {
    let mut wal = path.as_os_str().to_owned();
    wal.push("-wal");
    snapshot(path)[0] == before[0]
        && std::fs::metadata(PathBuf::from(wal)).map_or(true, |m| m.len() == 0)
}

fn export(from: &Path, to: &Path) -> Command {
    let mut command = trustcbr();
    command.args(["cases", "export"]).arg(from).arg(to);
    command
}

#[test]
fn an_export_never_writes_over_its_source_or_another_case_base() {
    let bases = Bases::new();
    let base = bases.path("base.db");
    let other = bases.path("other.db");
    bases.import(other.to_str().unwrap());
    let before = [snapshot(&base), snapshot(&other)];
    let unchanged_both = || unchanged(&base, &before[0]) && unchanged(&other, &before[1]);

    // The same file, and another case base: neither is a RON file.
    for out in [&base, &other] {
        let stderr = refused(&mut export(&base, out));
        assert!(
            stderr.contains(&format!(
                "{}: an export is a RON case file and its name must end in `.ron`",
                out.display()
            )),
            "{stderr}"
        );
    }
    // A `.ron` name that resolves to the source (a symlink) or to another base.
    let to_source = bases.path("to-source.ron");
    std::os::unix::fs::symlink(&base, &to_source).unwrap();
    let stderr = refused(&mut export(&base, &to_source));
    assert!(
        stderr.contains(&format!(
            "{}: this is the case base being exported ({}); give the export another file name",
            to_source.display(),
            base.display()
        )),
        "{stderr}"
    );
    let to_other = bases.path("to-other.ron");
    std::os::unix::fs::symlink(&other, &to_other).unwrap();
    let stderr = refused(&mut export(&base, &to_other));
    assert!(
        stderr.contains(&format!(
            "{}: exists and is not an earlier export (a symbolic link: nothing is written through one, nor is what it points to changed); `cases export` writes over nothing else: give a new file name",
            to_other.display()
        )),
        "{stderr}"
    );
    assert!(unchanged_both());

    // A RON case base exported onto itself, however spelled: a hard link, `dir/../`.
    let exported = bases.path("exported.ron");
    succeed(&mut export(&base, &exported));
    let text = std::fs::read(&exported).unwrap();
    let hard = bases.path("hard.ron");
    std::fs::hard_link(&exported, &hard).unwrap();
    let dotted = bases.path("sub/../exported.ron");
    std::fs::create_dir(bases.path("sub")).unwrap();
    for out in [&exported, &hard, &dotted] {
        let stderr = refused(&mut export(&exported, out));
        assert!(
            stderr.contains("this is the case base being exported"),
            "{stderr}"
        );
    }
    assert_eq!(std::fs::read(&exported).unwrap(), text);

    // Any other existing file is kept: text that is no case file, a hand-written case file.
    let notes = bases.path("notes.ron");
    std::fs::write(&notes, "my notes").unwrap();
    let stderr = refused(&mut export(&base, &notes));
    assert!(
        stderr.contains("exists and is not an earlier export (not a RON case file)"),
        "{stderr}"
    );
    assert_eq!(std::fs::read(&notes).unwrap(), b"my notes");
    let hand = bases.path("three.ron");
    let hand_text = std::fs::read(&hand).unwrap();
    let stderr = refused(&mut export(&base, &hand));
    assert!(
        stderr.contains("a RON case file recording no behavior space"),
        "{stderr}"
    );
    assert_eq!(std::fs::read(&hand).unwrap(), hand_text);

    // An earlier export is replaced.
    let again = bases.path("again.ron");
    succeed(&mut export(&other, &again));
    succeed(&mut export(&base, &again));
    assert_eq!(std::fs::read(&again).unwrap(), text);
    assert!(unchanged_both());
}

/// SQLite files that are not case bases of ours, each made by `sql` on a fresh file in
/// rollback-journal mode, and what the refusal says.
const FOREIGN: [(&str, &str, &str); 5] = [
    (
        "inventory",
        "CREATE TABLE parts (name TEXT)",
        "an SQLite database with other tables (parts); give a new file name",
    ),
    (
        "lookalike",
        "CREATE TABLE trustcbr_identity (who TEXT); CREATE TABLE trustcbr_cases (what BLOB)",
        "the table trustcbr_identity has the columns (who TEXT), a case base's has (singleton INTEGER, format INTEGER, domain TEXT, space TEXT)",
    ),
    (
        "half",
        "CREATE TABLE trustcbr_cases (id INTEGER PRIMARY KEY, problem TEXT, solution TEXT)",
        "the table trustcbr_identity is missing",
    ),
    (
        "future",
        "CREATE TABLE trustcbr_identity (singleton INTEGER PRIMARY KEY, format INTEGER NOT NULL, domain TEXT NOT NULL, space TEXT NOT NULL);
         CREATE TABLE trustcbr_cases (id INTEGER PRIMARY KEY AUTOINCREMENT, problem TEXT NOT NULL, solution TEXT NOT NULL);
         INSERT INTO trustcbr_identity VALUES (1, 7, 'quick', '{}')",
        "format 7, this program reads format 1",
    ),
    (
        "nulls",
        "CREATE TABLE trustcbr_identity (singleton INTEGER, format INTEGER, domain TEXT, space TEXT);
         CREATE TABLE trustcbr_cases (id INTEGER, problem TEXT, solution TEXT);
         INSERT INTO trustcbr_identity VALUES (1, 1, NULL, NULL)",
        "the row of trustcbr_identity does not hold an integer format, a text domain and a text space",
    ),
];

#[test]
fn sqlite_files_that_are_not_case_bases_are_refused_untouched() {
    let bases = Bases::new();
    for (name, sql, reason) in FOREIGN {
        let path = bases.path(&format!("{name}.db"));
        rusqlite::Connection::open(&path)
            .unwrap()
            .execute_batch(sql)
            .unwrap();
        let before = snapshot(&path);
        assert_eq!(before[1..], [None, None], "{name}: no journal left");
        let shown = path.to_str().unwrap();
        let mut info = trustcbr();
        info.args(["cases", "info", shown]);
        let commands = [
            bases.import_command(shown),
            bases.serve_command(shown),
            info,
            export(&path, &bases.path(&format!("{name}.ron"))),
        ];
        for mut command in commands {
            let stderr = refused(&mut command);
            assert!(
                stderr.contains(&format!("{shown}: not a trustcbr case base: {reason}")),
                "{name}: {stderr}"
            );
            assert_eq!(snapshot(&path), before, "{name}: the file was changed");
        }
        assert!(!bases.path(&format!("{name}.ron")).exists());
    }
}

#[test]
fn import_refuses_a_case_base_that_serve_refuses_before_appending() {
    let bases = Bases::new();
    let base = bases.path("base.db");
    let connection = rusqlite::Connection::open(&base).unwrap();
    connection
        .execute(
            "UPDATE trustcbr_cases SET problem = 'not json' WHERE id = 2",
            [],
        )
        .unwrap();
    drop(connection);
    let before = snapshot(&base);
    let shown = base.to_str().unwrap();
    let mut info = trustcbr();
    info.args(["cases", "info", shown]);
    for mut command in [
        bases.serve_command(shown),
        info,
        bases.import_command(shown),
    ] {
        let stderr = refused(&mut command);
        assert!(
            stderr.contains(&format!("{shown}: not a trustcbr case base: case #2: ")),
            "{stderr}"
        );
        assert!(unchanged(&base, &before));
    }
    // A case out of the domain's space: refused by serve and import alike.
    let connection = rusqlite::Connection::open(&base).unwrap();
    connection
        .execute(
            "UPDATE trustcbr_cases SET problem = '[]', solution = '[9, 9]' WHERE id = 2",
            [],
        )
        .unwrap();
    drop(connection);
    let before = snapshot(&base);
    let stderr = refused(&mut bases.import_command(shown));
    assert!(
        stderr.contains(&format!(
            "{shown}: case #2 does not fit this domain's behavior space"
        )),
        "{stderr}"
    );
    assert!(unchanged(&base, &before));
}

/// Whether this process runs as root, whom file permissions do not stop.
fn root() -> bool {
    let id = Command::new("id").arg("-u").output().unwrap();
    String::from_utf8_lossy(&id.stdout).trim() == "0"
}

/// `command` run so that `dir` is read-only to it, and whether it really is: for root, in a
/// mount namespace where `dir` is bound read-only (where namespaces are not permitted,
/// `command` as it is: nothing makes a folder read-only to root then); for anyone else,
/// with the write permissions of the folder and its files removed.
fn read_only(dir: &Path, command: &Command) -> (Command, bool) {
    let mut same = Command::new(command.get_program());
    same.args(command.get_args());
    if !root() {
        use std::os::unix::fs::PermissionsExt;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o444)).unwrap();
        }
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o555)).unwrap();
        return (same, true);
    }
    let permitted = Command::new("unshare")
        .args(["--mount", "true"])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !permitted {
        return (same, false);
    }
    let mut wrapped = Command::new("unshare");
    wrapped
        .args([
            "--mount",
            "sh",
            "-c",
            r#"mount --bind -o ro "$0" "$0" && exec "$@""#,
        ])
        .arg(dir)
        .arg(command.get_program())
        .args(command.get_args());
    (wrapped, true)
}

#[test]
fn info_and_export_read_a_case_base_on_a_read_only_file_system() {
    let bases = Bases::new();
    let dir = bases.path("ro");
    std::fs::create_dir(&dir).unwrap();
    let base = dir.join("base.db");
    bases.import(base.to_str().unwrap());
    let before = snapshot(&base);
    assert_eq!(before[1..], [None, None]);
    let out = bases.path("copy.ron");
    let mut info = trustcbr();
    info.args(["cases", "info"]).arg(&base);
    for command in [info, export(&base, &out)] {
        let (mut run, really) = read_only(&dir, &command);
        if !really {
            eprintln!(
                "no read-only mount is permitted here: checking only that nothing is written"
            );
        }
        let stdout = succeed(&mut run);
        assert!(
            stdout.contains("cases:     3 (ids 1 to 3)") || stdout.starts_with("wrote 3 cases"),
            "{stdout}"
        );
        // Nothing written: not the file, and on a read-only file system nothing beside it.
        if really {
            assert_eq!(snapshot(&base), before, "the case base was changed");
        } else {
            assert!(unchanged(&base, &before), "the case base was changed");
        }
    }
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o755)).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.matches("solution:").count(), 3, "{text}");
}

#[test]
fn passwords_are_never_shown() {
    let bases = Bases::new();
    // Nothing listens on port 1: every command fails to connect and says so.
    for url in [
        "postgres://robot:s3cret-pw@127.0.0.1:1/fleet",
        "postgres://127.0.0.1:1/fleet?user=robot&password=s3cret-pw",
        "postgresql://127.0.0.1:1/fleet?password=s3cret-pw&user=robot",
    ] {
        let mut info = trustcbr();
        info.args(["cases", "info", url]);
        for mut command in [bases.serve_command(url), info, bases.import_command(url)] {
            let output = command.stdin(Stdio::null()).output().unwrap();
            let all = format!(
                "{}{}",
                String::from_utf8_lossy(&output.stdout),
                String::from_utf8_lossy(&output.stderr)
            );
            assert_eq!(output.status.code(), Some(1), "{all}");
            assert!(!all.contains("s3cret"), "{all}");
            assert!(all.contains("***"), "{all}");
        }
    }
}

/// A fresh database on the test server, dropped at the end; `None` (with a message) when
/// no server is named, which CI does not allow.
struct TestDatabase {
    admin: postgres::Client,
    name: String,
    url: String,
    base: String,
}

impl TestDatabase {
    fn create(name: &str) -> Option<Self> {
        let Ok(server) = std::env::var("TRUSTCBR_TEST_POSTGRES") else {
            assert!(
                std::env::var("CI").as_deref() != Ok("true"),
                "CI must run the PostgreSQL tests: set TRUSTCBR_TEST_POSTGRES (.ci/run starts a server)"
            );
            eprintln!("skipped: set TRUSTCBR_TEST_POSTGRES=postgres://... to run {name}");
            return None;
        };
        let name = format!("trustcbr_{name}_{}", std::process::id());
        let mut admin = postgres::Client::connect(&server, postgres::NoTls).unwrap();
        admin
            .batch_execute(&format!(
                "DROP DATABASE IF EXISTS {name}; CREATE DATABASE {name}"
            ))
            .unwrap_or_else(|_| {
                admin
                    .batch_execute(&format!("CREATE DATABASE {name}"))
                    .unwrap()
            });
        let (base, _) = server.rsplit_once('/').unwrap();
        let url = format!("{base}/{name}");
        Some(Self {
            admin,
            name,
            url,
            base: base.to_owned(),
        })
    }

    fn client(&self) -> postgres::Client {
        postgres::Client::connect(&self.url, postgres::NoTls).unwrap()
    }
}

impl Drop for TestDatabase {
    fn drop(&mut self) {
        let drop = format!("DROP DATABASE {} WITH (FORCE)", self.name);
        self.admin.batch_execute(&drop).ok();
    }
}

/// The rows of both tables, as text, in a fixed order.
fn dump(client: &mut postgres::Client) -> Vec<String> {
    ["trustcbr_identity", "trustcbr_cases"]
        .iter()
        .flat_map(|table| {
            client
                .query(&format!("SELECT t::text FROM {table} t ORDER BY 1"), &[])
                .map(|rows| rows.iter().map(|r| r.get::<_, String>(0)).collect())
                .unwrap_or_else(|e| vec![format!("{table}: {e}")])
        })
        .collect()
}

#[test]
fn postgres_tables_of_our_names_that_are_not_ours_are_refused_without_panic() {
    let Some(db) = TestDatabase::create("foreign") else {
        return;
    };
    let bases = Bases::new();
    let cases: [(&str, &str); 3] = [
        (
            "CREATE TABLE trustcbr_identity (singleton integer, format text, domain text, space text);
             CREATE TABLE trustcbr_cases (id bigint, problem text, solution text);
             INSERT INTO trustcbr_identity VALUES (1, 'one', 'quick', '{}')",
            "the table trustcbr_identity has the columns (singleton integer, format text, domain text, space text), a case base's has (singleton integer, format bigint, domain text, space text)",
        ),
        (
            "CREATE TABLE trustcbr_identity (singleton integer, format bigint, domain text, space text);
             CREATE TABLE trustcbr_cases (id bigint, problem text, solution text);
             INSERT INTO trustcbr_identity VALUES (1, 1, NULL, NULL)",
            "the row of trustcbr_identity: error deserializing column 1",
        ),
        (
            "CREATE TABLE trustcbr_cases (id integer, problem jsonb)",
            "the table trustcbr_cases has the columns (id integer, problem jsonb)",
        ),
    ];
    for (sql, reason) in cases {
        let mut client = db.client();
        client
            .batch_execute(
                "DROP TABLE IF EXISTS trustcbr_identity; DROP TABLE IF EXISTS trustcbr_cases",
            )
            .unwrap();
        client.batch_execute(sql).unwrap();
        let before = dump(&mut client);
        let mut info = trustcbr();
        info.args(["cases", "info", &db.url]);
        for mut command in [
            bases.serve_command(&db.url),
            info,
            bases.import_command(&db.url),
        ] {
            let stderr = refused(&mut command);
            assert!(
                stderr.contains(&format!("{}: not a trustcbr case base: {reason}", db.url)),
                "{stderr}"
            );
            assert_eq!(dump(&mut client), before);
        }
    }
    // A NULL in a case's row of otherwise fitting tables.
    let mut client = db.client();
    client
        .batch_execute(
            "DROP TABLE IF EXISTS trustcbr_identity; DROP TABLE IF EXISTS trustcbr_cases;
             CREATE TABLE trustcbr_identity (singleton integer, format bigint, domain text, space text);
             CREATE TABLE trustcbr_cases (id bigint, problem text, solution text);
             INSERT INTO trustcbr_cases VALUES (1, NULL, '[1, 1]')",
        )
        .unwrap();
    let space: String = rusqlite::Connection::open(bases.path("base.db"))
        .unwrap()
        .query_row("SELECT space FROM trustcbr_identity", [], |r| r.get(0))
        .unwrap();
    client
        .execute(
            "INSERT INTO trustcbr_identity VALUES (1, 1, 'quick', $1)",
            &[&space],
        )
        .unwrap();
    let stderr = refused(trustcbr().args(["cases", "info", &db.url]));
    assert!(
        stderr.contains(&format!(
            "{}: not a trustcbr case base: case #1: error deserializing column 1",
            db.url
        )),
        "{stderr}"
    );
}

#[test]
fn a_select_only_role_reads_a_postgres_case_base() {
    let Some(db) = TestDatabase::create("reader") else {
        return;
    };
    let bases = Bases::new();
    bases.import(&db.url);
    let role = format!("trustcbr_reader_{}", std::process::id());
    let mut client = db.client();
    client
        .batch_execute(&format!(
            "DROP ROLE IF EXISTS {role}; CREATE ROLE {role} LOGIN;
             REVOKE ALL ON SCHEMA public FROM PUBLIC;
             GRANT USAGE ON SCHEMA public TO {role};
             GRANT SELECT ON trustcbr_identity, trustcbr_cases TO {role}"
        ))
        .unwrap();
    let before = dump(&mut client);
    let (scheme, rest) = db.base.split_once("://").unwrap();
    let host = rest.rsplit_once('@').map_or(rest, |(_, host)| host);
    let url = format!("{scheme}://{role}@{host}/{}", db.name);
    let info = succeed(trustcbr().args(["cases", "info", &url]));
    assert!(info.contains("cases:     3 (ids 1 to 3)"), "{info}");
    let out = bases.path("fleet.ron");
    let said = succeed(trustcbr().args(["cases", "export", &url]).arg(&out));
    assert!(said.starts_with("wrote 3 cases"), "{said}");
    assert_eq!(dump(&mut client), before);
    drop(client);
    drop(db);
    let mut admin = postgres::Client::connect(
        &std::env::var("TRUSTCBR_TEST_POSTGRES").unwrap(),
        postgres::NoTls,
    )
    .unwrap();
    admin.batch_execute(&format!("DROP ROLE {role}")).unwrap();
}

#[test]
fn passwords_are_not_shown_in_the_startup_line() {
    let Some(db) = TestDatabase::create("secret") else {
        return;
    };
    let bases = Bases::new();
    // The test server trusts loopback connections, so any password is accepted.
    let (scheme, rest) = db.url.split_once("://").unwrap();
    let (user, rest) = rest.split_once('@').unwrap();
    for url in [
        format!("{scheme}://{user}:s3cret-pw@{rest}"),
        format!("{}?password=s3cret-pw", db.url),
    ] {
        let output = bases
            .serve_command(&url)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{stderr}");
        assert!(stderr.contains("cases loaded from"), "{stderr}");
        assert!(!stderr.contains("s3cret"), "{stderr}");
        assert!(stderr.contains("***"), "{stderr}");
    }
}

#[test]
fn an_export_larger_than_a_config_is_read_back() {
    let bases = Bases::new();
    let exported = bases.path("exported.ron");
    succeed(&mut export(&bases.path("base.db"), &exported));
    // The three cases repeated to some 3 MB: more than the 1 MiB of a config file.
    let text = std::fs::read_to_string(&exported).unwrap();
    let start = text.find("cases: [").unwrap() + "cases: [".len();
    let end = text.rfind(']').unwrap();
    let cases = text[start..end].trim().trim_end_matches(',');
    let copies = 3_000_000 / cases.len() + 1;
    let big = format!(
        "{}{}{}",
        &text[..start],
        format!("{cases},").repeat(copies),
        &text[end..]
    );
    assert!(big.len() > 2 << 20);
    let big_path = bases.path("big.ron");
    std::fs::write(&big_path, &big).unwrap();
    let count = copies * 3;
    let info = succeed(trustcbr().args(["cases", "info"]).arg(&big_path));
    assert!(info.contains(&format!("cases:     {count} ")), "{info}");
    let big_db = bases.path("big.db");
    let said = succeed(
        trustcbr()
            .args(["cases", "import"])
            .arg(&big_path)
            .arg(&big_db)
            .arg("--domain")
            .arg(bases.domain()),
    );
    assert!(
        said.starts_with(&format!("imported {count} cases")),
        "{said}"
    );
    let output = bases
        .serve_command(big_path.to_str().unwrap())
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.contains(&format!("{count} cases loaded")),
        "{stderr}"
    );
}

#[test]
fn serve_checks_its_options_before_creating_a_case_base() {
    let bases = Bases::new();
    let new = bases.path("new.db");
    let shown = new.to_str().unwrap();
    // Bound first, so the second server's port is taken.
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().to_string();
    for (options, expected) in [
        (&["--listen", "192.0.2.1:7878"][..], "192.0.2.1:7878"),
        (&["--listen", &port], "cannot listen on"),
        (
            &["--listen", "127.0.0.1:0", "--idle-timeout", "0"],
            "--idle-timeout must be a number of seconds more than 0 and at most 86400 (a day), got 0",
        ),
    ] {
        let stderr = refused(bases.serve_command(shown).args(options));
        assert!(stderr.contains(expected), "{options:?}: {stderr}");
        assert!(!new.exists(), "{options:?} created the case base");
    }
}

#[test]
fn importing_a_file_twice_is_warned_of() {
    let bases = Bases::new();
    let base = bases.path("base.db");
    let output = bases
        .import_command(base.to_str().unwrap())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "warning: 3 of them were already in {} (the same evaluated pairs and solution): is {} imported twice? It now holds them twice",
            base.display(),
            bases.path("three.ron").display()
        )),
        "{stderr}"
    );
    // A RON file as the target: refused, with a target that would do.
    let target = bases.path("three-copy.ron");
    let stderr = refused(&mut bases.import_command(target.to_str().unwrap()));
    assert!(
        stderr.contains(&format!(
            "{}: RON case files are read-only; import the cases into an SQLite file or a postgres:// URL instead, e.g. `{}`",
            target.display(),
            bases.path("three-copy.db").display()
        )),
        "{stderr}"
    );
    assert!(!target.exists());
}

#[test]
fn a_case_base_of_another_domain_of_the_same_space_is_refused_untouched() {
    let bases = Bases::new();
    let base = bases.path("base.db");
    let before = snapshot(&base);
    // The same domain file under another name: the same space, another domain.
    let depot = bases.path("depot.ron");
    std::fs::copy(bases.domain(), &depot).unwrap();
    let expected = format!(
        "error: {}: the case base was learned in domain `{}`, not `{}` (domains are compared by name, a domain file by its file name); serve or import it with the domain it was learned in\n",
        base.display(),
        bases.domain().display(),
        depot.display()
    );
    let mut serve = trustcbr();
    serve
        .args(["serve", "--domain"])
        .arg(&depot)
        .args(["--cases", base.to_str().unwrap()]);
    assert_eq!(refused(&mut serve), expected);
    let mut import = trustcbr();
    import
        .args(["cases", "import"])
        .arg(bases.path("three.ron"))
        .arg(&base)
        .arg("--domain")
        .arg(&depot);
    assert_eq!(refused(&mut import), expected);
    assert!(unchanged(&base, &before));
    // An export records its domain: importing it into a new base for another domain is
    // refused too, and creates nothing.
    let exported = bases.path("export.ron");
    succeed(&mut export(&base, &exported));
    let fresh = bases.path("fresh.db");
    let mut import = trustcbr();
    import
        .args(["cases", "import"])
        .arg(&exported)
        .arg(&fresh)
        .arg("--domain")
        .arg(&depot);
    assert_eq!(
        refused(&mut import),
        expected.replace(base.to_str().unwrap(), exported.to_str().unwrap())
    );
    assert!(!fresh.exists());
    // The domain file moved to another folder keeps its bases.
    let moved = bases.path("moved");
    std::fs::create_dir(&moved).unwrap();
    std::fs::rename(bases.domain(), moved.join("quick.ron")).unwrap();
    let mut again = trustcbr();
    again
        .args(["cases", "import"])
        .arg(&exported)
        .arg(&fresh)
        .arg("--domain")
        .arg(moved.join("quick.ron"));
    succeed(&mut again);
}

/// A tmpfs mounted at a folder of its own for the life of the value (root only), so a
/// test can turn it read-only; unmounted when dropped, even when the test fails.
struct Tmpfs(PathBuf);

impl Tmpfs {
    /// A fresh tmpfs at `dir`, or `None` where this process may not mount one.
    fn at(dir: &Path) -> Option<Self> {
        std::fs::create_dir_all(dir).unwrap();
        let mounted = Command::new("mount")
            .args(["-t", "tmpfs", "-o", "size=8m", "tmpfs"])
            .arg(dir)
            .status()
            .is_ok_and(|s| s.success());
        mounted.then(|| Self(dir.to_owned()))
    }

    fn read_only(&self) {
        let status = Command::new("mount")
            .args(["-o", "remount,ro"])
            .arg(&self.0)
            .status()
            .unwrap();
        assert!(status.success());
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        Command::new("umount").arg(&self.0).status().ok();
    }
}

/// `serve` of a case base on a read-only file system says why it cannot open it (it said
/// only "unable to open database file"), and a new one there why it cannot be made;
/// `cases info` still reads it.
#[test]
fn serve_on_a_read_only_file_system_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let Some(fs) = Tmpfs::at(&dir.path().join("ro")) else {
        eprintln!("skipped: this process may not mount a tmpfs (it needs root)");
        return;
    };
    let base = fs.0.join("cases.db");
    let serve = |cases: &Path| {
        let output = Command::new(env!("CARGO_BIN_EXE_trustcbr"))
            .args(["serve", "--domain", "movement", "--cases"])
            .arg(cases)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        (
            output.status.success(),
            String::from_utf8_lossy(&output.stderr).into_owned(),
        )
    };
    let (created, stderr) = serve(&base);
    assert!(created, "{stderr}");
    fs.read_only();
    let (served, stderr) = serve(&base);
    assert!(!served);
    assert!(
        stderr.contains("the file cannot be opened for writing (Read-only file system")
            && stderr.contains("give a writable place"),
        "{stderr}"
    );
    let (served, stderr) = serve(&fs.0.join("new.db"));
    assert!(!served);
    assert!(
        stderr.contains("cannot create the case base beside it: Read-only file system"),
        "{stderr}"
    );
    let info = Command::new(env!("CARGO_BIN_EXE_trustcbr"))
        .args(["cases", "info"])
        .arg(&base)
        .output()
        .unwrap();
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
}
