//! `clapper serve`: the web application on a local port.

use std::io::Write as _;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};

use anyhow::{Context, Result};
use clap::Args;
use clapper_web::Limits;

#[derive(Args, Debug)]
pub struct ServeArgs {
    /// Port to listen on (0: any free port; the address is printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// Address to listen on. The default, loopback, is reachable only from
    /// this machine; give 0.0.0.0 to share it on a network you trust.
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    pub host: IpAddr,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// Computations running at once (further requests wait).
    #[arg(long, value_name = "N", default_value_t = Limits::default().max_jobs)]
    pub max_jobs: usize,
    /// Most chart points in one chart request.
    #[arg(long, value_name = "N", default_value_t = Limits::default().max_chart_points)]
    pub max_chart_points: usize,
    /// Also answer requests to this host name (repeatable; `*.example.org`
    /// for every name under it). Loopback names and IP addresses are
    /// always answered; any other name is refused (403), so that a web page
    /// elsewhere cannot drive this server through your browser.
    #[arg(long, value_name = "NAME")]
    pub allow_host: Vec<String>,
}

pub fn run(args: ServeArgs) -> Result<()> {
    if args.max_jobs == 0 || args.max_jobs > 1024 {
        anyhow::bail!("--max-jobs {} is out of range: 1 to 1024", args.max_jobs);
    }
    if args.max_chart_points == 0 || args.max_chart_points > clapper_core::chart::MAX_POINTS {
        anyhow::bail!(
            "--max-chart-points {} is out of range: 1 to {}",
            args.max_chart_points,
            clapper_core::chart::MAX_POINTS
        );
    }
    let hosts = clapper_web::AllowedHosts::with(&args.allow_host).map_err(anyhow::Error::msg)?;
    let limits = Limits {
        max_jobs: args.max_jobs,
        max_chart_points: args.max_chart_points,
        max_connections: connection_room(),
        ..Limits::default()
    };
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the server's runtime")?;
    let served = runtime.block_on(async move {
        let addr = SocketAddr::new(args.host, args.port);
        let listener = tokio::net::TcpListener::bind(addr)
            .await
            .with_context(|| format!("cannot listen on {addr} (is the port in use? try --port 0)"))?;
        let local = listener.local_addr()?;
        let url = format!("http://{local}/");
        println!("clapper is serving on {url}  (API: {url}api; Ctrl-C to stop)");
        std::io::stdout().flush()?;
        if !args.host.is_loopback() {
            eprintln!("warning: listening on {} is reachable from other machines", args.host);
        }
        if args.open {
            open_browser(&url);
        }
        let shutdown = async {
            let _ = tokio::signal::ctrl_c().await;
        };
        clapper_web::serve(listener, limits, hosts, shutdown).await?;
        println!("stopped");
        Ok(())
    });
    // A computation still running (a chart past its client) is not waited
    // for: the process is ending.
    runtime.shutdown_timeout(std::time::Duration::from_millis(200));
    served
}

/// Most connections to hold open: half the open files this process may
/// have, after raising its soft limit as far as the system lets (to
/// 65,536 at most), between 512 and 16,384. Clients that trickle their
/// requests are cut off within seconds (`Limits::min_upload_rate`), but
/// while they last a thousand of them must still leave room for the page
/// and `/api/health`; the other half of the files is for the server's own.
fn connection_room() -> usize {
    const FLOOR: usize = 512;
    #[cfg(unix)]
    {
        let files = rlimit::increase_nofile_limit(65_536).unwrap_or(1024);
        usize::try_from(files / 2).unwrap_or(FLOOR).clamp(FLOOR, 16_384)
    }
    #[cfg(not(unix))]
    {
        FLOOR
    }
}

/// The command that opens a URL in a browser: `$BROWSER` (a program and
/// its options) if set, else the desktop's own opener.
fn browser_command() -> Vec<String> {
    if let Some(b) = std::env::var("BROWSER").ok().filter(|b| !b.trim().is_empty()) {
        // A list of browsers to try is `:`-separated; the first is taken.
        let first = b.split(':').next().unwrap_or(&b);
        return first.split_whitespace().map(String::from).collect();
    }
    let cmd: &[&str] = if cfg!(target_os = "macos") {
        &["open"]
    } else if cfg!(windows) {
        &["cmd", "/C", "start", ""]
    } else {
        &["xdg-open"]
    };
    cmd.iter().map(|s| s.to_string()).collect()
}

/// How long an opener has to fail in for its failure to be said: after
/// that, its exit is the browser's own (xdg-open may wait for it).
const OPENER_GRACE: std::time::Duration = std::time::Duration::from_secs(10);

/// Ask the desktop to open `url`, without its output (xdg-open with no
/// browser prints a line for every browser it tried); if it cannot, say so
/// in one line. Not `opener`: it discards xdg-open's exit status, so a
/// failure could not be said at all.
fn open_browser(url: &str) {
    let cmd = browser_command();
    let spawned = std::process::Command::new(&cmd[0])
        .args(&cmd[1..])
        .arg(url)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
    match spawned {
        Err(_) => cannot_open(url),
        // Waited for on a thread of its own (which also reaps it): the
        // server is already answering.
        Ok(mut child) => {
            let started = std::time::Instant::now();
            let url = url.to_string();
            std::thread::spawn(move || {
                if let Ok(status) = child.wait() {
                    if !status.success() && started.elapsed() < OPENER_GRACE {
                        cannot_open(&url);
                    }
                }
            });
        }
    }
}

/// The one line said when no browser could be opened.
fn cannot_open(url: &str) {
    eprintln!("could not open a browser: open {url} yourself");
}
