//! Shared by the `mx graph` tests: the 6-clip library, one uninterrupted
//! build of it, the binary, byte comparison of graphs, and checks that a
//! folder holds no partial file.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;
use std::time::Instant;

/// Six short locomotion clips of the shared in-betweening folder.
pub const CLIPS: [&str; 6] = [
    "bandai1_dash_active_001",
    "bandai1_dash_childish_001",
    "bandai1_run_active_001",
    "bandai1_run_old_001",
    "bandai1_walk-left_active_001",
    "bandai1_walk-right_active_001",
];

/// Small on purpose: one point per pair, short gaps, a cheap SP (the test profile is opt-level 1).
pub const TEST_SETTINGS: [&str; 16] = [
    "--k",
    "1",
    "--threshold",
    "0.12",
    "--min-gap",
    "3",
    "--max-gap",
    "6",
    "--context",
    "4",
    "--coefficients",
    "3",
    "--samples",
    "12",
    "--iterations",
    "30",
];

pub fn mx_bin() -> &'static str {
    env!("CARGO_BIN_EXE_mx")
}

pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

pub fn have(program: &str) -> bool {
    Command::new("sh")
        .arg("-c")
        .arg(format!("command -v {program}"))
        .output()
        .is_ok_and(|o| o.status.success())
}

/// A symlink to `file` in `dir` (the shared data is never copied).
pub fn link(file: &Path, dir: &Path) {
    std::os::unix::fs::symlink(file, dir.join(file.file_name().unwrap())).unwrap();
}

/// `mx graph build CLIPS --out OUT` with the test settings and no Slurm variables.
pub fn build_cmd(clips: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut c = Command::new(mx_bin());
    c.args(["graph", "build"])
        .arg(clips)
        .arg("--out")
        .arg(out)
        .args(TEST_SETTINGS)
        .arg("--quiet")
        .args(extra)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .env_remove("SLURM_ARRAY_TASK_MIN");
    c
}

pub fn merge(out: &Path) {
    let o = Command::new(mx_bin())
        .args(["graph", "merge"])
        .arg(out)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "merge: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

pub struct Baseline {
    pub clips: tempfile::TempDir,
    pub out: tempfile::TempDir,
    /// Wall time of the uninterrupted build.
    pub seconds: f64,
}

/// The clip folder (links to the 6 clips) and one uninterrupted 1-shard build.
pub fn baseline() -> Option<&'static Baseline> {
    static BASE: OnceLock<Option<Baseline>> = OnceLock::new();
    BASE.get_or_init(|| {
        let shared = crate::common::shared_dir()?;
        let clips = tempfile::tempdir().unwrap();
        for n in CLIPS {
            link(
                &shared.join(format!("data/inbetween/{n}.bvh")),
                clips.path(),
            );
        }
        let out = tempfile::tempdir().unwrap();
        let log = out.path().join("log.jsonl");
        let t = Instant::now();
        let o = build_cmd(clips.path(), out.path(), &["--log", log.to_str().unwrap()])
            .output()
            .unwrap();
        let seconds = t.elapsed().as_secs_f64();
        let err = String::from_utf8_lossy(&o.stderr);
        eprintln!("baseline build, {seconds:.1} s: {err}");
        assert!(o.status.success(), "{err}");
        // one machine-readable line per finished pair
        let lines = std::fs::read_to_string(&log).unwrap();
        assert_eq!(lines.lines().count(), 30);
        for l in lines.lines() {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            assert!(v["sp_seconds"].is_number() && v["a"].is_string(), "{l}");
        }
        Some(Baseline {
            clips,
            out,
            seconds,
        })
    })
    .as_ref()
}

/// graph.json and every transition BVH, by name.
pub fn graph_files(out: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut m = BTreeMap::new();
    m.insert(
        "graph.json".to_string(),
        std::fs::read(out.join("graph.json")).unwrap(),
    );
    for e in std::fs::read_dir(out.join("transitions")).unwrap() {
        let p = e.unwrap().path();
        m.insert(
            format!("transitions/{}", p.file_name().unwrap().to_string_lossy()),
            std::fs::read(&p).unwrap(),
        );
    }
    m
}

pub fn assert_same_graph(expected: &Path, got: &Path) {
    let (a, b) = (graph_files(expected), graph_files(got));
    let names_a: Vec<&String> = a.keys().collect();
    let names_b: Vec<&String> = b.keys().collect();
    assert_eq!(names_a, names_b, "the same files");
    for (k, v) in &a {
        assert!(v == &b[k], "{k} differs");
    }
}

/// Every file under `dir`, recursively.
fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            files(&p, out);
        } else {
            out.push(p);
        }
    }
}

/// Temporary files (`.name.pid.n.tmp`) left under `dir`.
pub fn temporaries(dir: &Path) -> Vec<String> {
    let mut all = vec![];
    files(dir, &mut all);
    all.iter()
        .filter(|p| p.file_name().unwrap().to_string_lossy().ends_with(".tmp"))
        .map(|p| p.display().to_string())
        .collect()
}

/// Every output file (not a writer's temporary) reads back whole.
pub fn assert_no_partial_file(dir: &Path) {
    let mut all = vec![];
    files(dir, &mut all);
    for p in all {
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if name.starts_with('.') && name.ends_with(".tmp") {
            continue;
        }
        if name.ends_with(".json") {
            let text = std::fs::read_to_string(&p).unwrap();
            assert!(
                serde_json::from_str::<serde_json::Value>(&text).is_ok(),
                "partial {}",
                p.display()
            );
        } else if name.ends_with(".bvh") {
            assert!(
                mx::mocap::bvh::read_file(&p).is_ok(),
                "partial {}",
                p.display()
            );
        }
    }
}

/// SplitMix64, for kill moments from a printed seed.
pub struct SplitMix(pub u64);

impl SplitMix {
    pub fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A single-node Slurm cluster on 127.0.0.1 (munged, slurmctld, slurmd as
/// children, all state in a temporary folder), stopped on drop, also when
/// the test fails.
pub struct Slurm {
    pub dir: tempfile::TempDir,
    pub conf: PathBuf,
    children: Vec<(String, std::process::Child)>,
}

impl Drop for Slurm {
    fn drop(&mut self) {
        // daemons first (slurmctld stops its slurmscriptd on SIGTERM), munged last
        for (name, c) in self.children.iter_mut().rev() {
            let _ = Command::new("kill")
                .arg("-TERM")
                .arg(c.id().to_string())
                .status();
            let t = Instant::now();
            while t.elapsed().as_secs_f64() < 5.0 {
                if let Ok(Some(_)) = c.try_wait() {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(50));
            }
            if !matches!(c.try_wait(), Ok(Some(_))) {
                eprintln!("{name} ignored SIGTERM: killing it");
                let _ = c.kill();
                let _ = c.wait();
            }
        }
    }
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

impl Slurm {
    /// The Slurm programs this needs, present?
    pub fn available() -> bool {
        ["munged", "slurmctld", "slurmd", "sbatch", "sinfo"]
            .iter()
            .all(|p| have(p))
    }

    fn log(&self, name: &str) -> String {
        std::fs::read_to_string(self.dir.path().join(name)).unwrap_or_default()
    }

    /// Every log, for a failure message.
    pub fn logs(&self) -> String {
        [
            "munged.log",
            "slurmctld.log",
            "slurmd.log",
            "slurmctld.out",
            "slurmd.out",
        ]
        .iter()
        .map(|n| format!("--- {n}\n{}", self.log(n)))
        .collect()
    }

    pub fn client(&self, program: &str) -> Command {
        let mut c = Command::new(program);
        c.env("SLURM_CONF", &self.conf);
        c
    }

    /// Starts munged, slurmctld and slurmd and waits until the node is idle.
    pub fn start() -> Result<Slurm, String> {
        let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
        let d = dir.path().to_path_buf();
        for sub in ["state", "spool"] {
            std::fs::create_dir_all(d.join(sub)).map_err(|e| e.to_string())?;
        }
        // a private munge key and socket: nothing of the machine's own munge is touched
        let key = d.join("munge.key");
        let bytes: Vec<u8> = {
            let mut r = SplitMix(std::process::id() as u64 ^ 0x5eed);
            (0..1024).map(|_| (r.unit() * 256.0) as u8).collect()
        };
        std::fs::write(&key, bytes).map_err(|e| e.to_string())?;
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&key, std::fs::Permissions::from_mode(0o600))
            .map_err(|e| e.to_string())?;
        let sock = d.join("munge.sock");
        let mem = 1000;
        let (ctld_port, d_port) = (free_port(), free_port());
        let conf = d.join("slurm.conf");
        let p = |s: &str| d.join(s).display().to_string();
        let text = format!(
            "ClusterName=mxtest\n\
             SlurmctldHost=localhost(127.0.0.1)\n\
             SlurmctldPort={ctld_port}\n\
             SlurmdPort={d_port}\n\
             AuthType=auth/munge\n\
             AuthInfo=socket={sock}\n\
             CredType=cred/munge\n\
             SlurmUser=root\n\
             SlurmdUser=root\n\
             StateSaveLocation={state}\n\
             SlurmdSpoolDir={spool}\n\
             SlurmctldPidFile={ctldpid}\n\
             SlurmdPidFile={dpid}\n\
             SlurmctldLogFile={ctldlog}\n\
             SlurmdLogFile={dlog}\n\
             ProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\n\
             SelectType=select/cons_tres\n\
             SelectTypeParameters=CR_CPU\n\
             ReturnToService=2\n\
             MpiDefault=none\n\
             SwitchType=switch/none\n\
             JobAcctGatherType=jobacct_gather/none\n\
             AccountingStorageType=accounting_storage/none\n\
             SchedulerType=sched/backfill\n\
             NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 RealMemory={mem} State=UNKNOWN\n\
             PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n",
            sock = sock.display(),
            state = p("state"),
            spool = p("spool"),
            ctldpid = p("slurmctld.pid"),
            dpid = p("slurmd.pid"),
            ctldlog = p("slurmctld.log"),
            dlog = p("slurmd.log"),
        );
        std::fs::write(&conf, text).map_err(|e| e.to_string())?;
        let mut s = Slurm {
            dir,
            conf: conf.clone(),
            children: vec![],
        };
        let spawn = |s: &mut Slurm, name: &str, cmd: &mut Command| -> Result<(), String> {
            let out =
                std::fs::File::create(d.join(format!("{name}.out"))).map_err(|e| e.to_string())?;
            let err = out.try_clone().map_err(|e| e.to_string())?;
            let c = cmd
                .stdout(out)
                .stderr(err)
                .spawn()
                .map_err(|e| format!("cannot start {name}: {e}"))?;
            s.children.push((name.to_string(), c));
            Ok(())
        };
        spawn(
            &mut s,
            "munged",
            Command::new("munged")
                .args(["-F", "-f", "-S"])
                .arg(&sock)
                .arg("--key-file")
                .arg(&key)
                .arg("--log-file")
                .arg(d.join("munged.log"))
                .arg("--pid-file")
                .arg(d.join("munged.pid"))
                .arg("--seed-file")
                .arg(d.join("munged.seed")),
        )?;
        let t = Instant::now();
        while !sock.exists() {
            if t.elapsed().as_secs() > 20 {
                return Err(format!("munged did not create its socket\n{}", s.logs()));
            }
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
        spawn(
            &mut s,
            "slurmctld",
            Command::new("slurmctld")
                .args(["-D", "-i", "-f"])
                .arg(&conf),
        )?;
        spawn(
            &mut s,
            "slurmd",
            Command::new("slurmd")
                .args(["-D", "-N", "localhost", "-f"])
                .arg(&conf),
        )?;
        let t = Instant::now();
        loop {
            let o = s.client("sinfo").args(["-h", "-o", "%T"]).output();
            if let Ok(o) = &o
                && String::from_utf8_lossy(&o.stdout).trim() == "idle"
            {
                return Ok(s);
            }
            let exited = s.children.iter_mut().find_map(|(name, c)| {
                c.try_wait()
                    .ok()
                    .flatten()
                    .map(|st| format!("{name} exited ({st})"))
            });
            if let Some(why) = exited {
                return Err(format!("{why}\n{}", s.logs()));
            }
            if t.elapsed().as_secs() > 60 {
                return Err(format!(
                    "the node did not become idle in 60 s\n{}",
                    s.logs()
                ));
            }
            std::thread::sleep(std::time::Duration::from_millis(250));
        }
    }
}
