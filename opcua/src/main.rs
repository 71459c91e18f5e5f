// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-opcua`: serves a procimgd instance's process image over OPC UA.

use anyhow::{Context, anyhow};
use clap::{Parser, Subcommand};
use procimg_client::{AttachOptions, Client};
use procimg_opcua::server::{Endpoint, Options, assemble};
use procimg_opcua::snapshot::{self, Snapshot};
use procimg_opcua::users::{self, Role, Users};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// Serve a procimgd instance's process image, states and items over OPC UA.
#[derive(Parser)]
#[command(version)]
struct Args {
    #[command(subcommand)]
    command: Option<Command>,
    /// The users file (`procimg-opcua user add` writes it): users who open sessions with a
    /// name and password, as readers or writers. Without it, sessions are anonymous and
    /// read only.
    #[arg(long, value_name = "FILE", alias = "writers")]
    users: Option<PathBuf>,
    /// The procimgd instance to serve.
    #[arg(
        long,
        short,
        env = "PROCIMG_INSTANCE",
        default_value = "procimg",
        value_name = "NAME"
    )]
    instance: String,
    /// Its CpIndex, as IO-Base names it: the n of the items' PNIO:[CTRL<n>].
    #[arg(
        long,
        default_value_t = 1,
        value_name = "N",
        value_parser = clap::value_parser!(u8).range(1..)
    )]
    cp_index: u8,
    /// Where the server listens and clients reach it: opc.tcp://HOST:PORT.
    #[arg(long, default_value = "opc.tcp://127.0.0.1:4840", value_name = "URL")]
    endpoint: String,
    /// The PKI folder: the server's certificate (made at first start), trusted/ and
    /// rejected/ client certificates.
    #[arg(long, default_value = "pki", value_name = "DIR")]
    pki: PathBuf,
    /// Offer the endpoint without security (policy None) beside the secure ones.
    #[arg(long)]
    insecure: bool,
    /// GSDML files, or folders of them, whose DataItems type the submodules' data: the tree
    /// then has a variable of the item's type (and one per named bit) below the bytes. A
    /// device's file is found by its VendorID and DeviceID.
    #[arg(long, value_name = "PATH")]
    gsdml: Vec<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// The users file.
    User {
        #[command(subcommand)]
        op: UserOp,
    },
}

#[derive(Subcommand)]
enum UserOp {
    /// Add user NAME to FILE (made if missing), or give them a new password or role; the
    /// password is read from standard input (its first line) and stored as a salted hash.
    Add {
        /// The users file.
        file: PathBuf,
        /// The user name.
        name: String,
        /// reader: read and subscribe; writer: also write outputs.
        #[arg(long, value_enum, default_value = "reader")]
        role: RoleArg,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum RoleArg {
    Reader,
    Writer,
}

fn main() {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .init();
    let args = Args::parse();
    let result = match args.command {
        Some(Command::User {
            op:
                UserOp::Add {
                    ref file,
                    ref name,
                    role,
                },
        }) => add_user(file, name, role),
        None => run(args),
    };
    if let Err(e) = result {
        eprintln!("procimg-opcua: {e:#}");
        std::process::exit(1);
    }
}

fn add_user(file: &std::path::Path, name: &str, role: RoleArg) -> anyhow::Result<()> {
    let mut password = String::new();
    std::io::stdin()
        .read_line(&mut password)
        .context("cannot read the password from standard input")?;
    let password = password.trim_end_matches(['\r', '\n']);
    let role = match role {
        RoleArg::Reader => Role::Reader,
        RoleArg::Writer => Role::Writer,
    };
    users::add(file, name, role, password)?;
    eprintln!("user {name:?} ({role:?}) in {}", file.display());
    Ok(())
}

fn run(args: Args) -> anyhow::Result<()> {
    let endpoint = Endpoint::parse(&args.endpoint).map_err(|e| anyhow!("--endpoint {e}"))?;
    let catalog = procimg_opcua::typed::Catalog::load(&args.gsdml)?;
    let users = Arc::new(match &args.users {
        Some(path) => Users::load(path)?,
        None => Users::default(),
    });
    let attach = {
        let instance = args.instance.clone();
        move |name: &'static str, slices: bool| -> anyhow::Result<Client> {
            Client::attach(
                &instance,
                AttachOptions::asynchronous(name).slice_access(slices),
            )
            .with_context(|| format!("cannot attach to procimgd instance {instance:?}"))
        }
    };
    let writing = attach("procimg-opcua-writer", true)?;
    let (write_tx, write_rx) = std::sync::mpsc::channel();
    let writer = {
        // After procimgd started anew with another layout: a writing client of that one.
        let again = {
            let attach = attach.clone();
            move || attach("procimg-opcua-writer", true).ok()
        };
        std::thread::Builder::new()
            .name("opcua-writes".into())
            .spawn(move || procimg_opcua::writer::run(writing, write_rx, again))
            .context("cannot start the writing thread")?
    };
    let (record_tx, record_rx) = std::sync::mpsc::channel();
    let recorder = {
        let instance = args.instance.clone();
        std::thread::Builder::new()
            .name("opcua-records".into())
            .spawn(move || procimg_opcua::records::run(&instance, record_rx))
            .context("cannot start the record thread")?
    };
    let mut client = attach("procimg-opcua", false)?;
    let layout = Arc::new(client.layout().clone());
    let report = snapshot::report(&client)?;
    let cycle = Duration::from_nanos(report.cycle_ns.max(1_000_000));
    // The first image: the server starts with values.
    let first = (0..1000)
        .find_map(|_| {
            let s = snapshot::take(&mut client, &layout, &report, None);
            if s.is_none() {
                std::thread::sleep(Duration::from_millis(5));
            }
            s
        })
        .ok_or_else(|| anyhow!("procimgd instance {:?} publishes no image", args.instance))?;
    let (tx, mut rx) = tokio::sync::watch::channel(Arc::new(first));
    let options = Options {
        instance: args.instance.clone(),
        controller: args.cp_index,
        endpoint: endpoint.clone(),
        pki: args.pki,
        insecure: args.insecure,
        cycle,
        users,
        pace: Arc::default(),
        catalog: Arc::new(catalog),
    };
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the async runtime")?;
    let stop = Arc::new(AtomicBool::new(false));
    let feeder = {
        let stop = stop.clone();
        let pace = options.pace.clone();
        std::thread::Builder::new()
            .name("image-feed".into())
            .spawn(move || {
                snapshot::feed(client, report, (&pace, cycle), tx, || {
                    stop.load(Ordering::Acquire)
                })
            })
            .context("cannot start the image thread")?
    };
    let result = runtime.block_on(async {
        let procimg_opcua::server::Assembled {
            server,
            handle,
            tree_nodes,
            mut tree,
            items,
            tree_namespace,
            types_namespace,
        } = assemble(&options, rx.clone(), write_tx, record_tx).map_err(|e| anyhow!("{e}"))?;
        let events = {
            let instance = options.instance.clone();
            let snapshots = rx.clone();
            let station = move || {
                let layout = snapshots.borrow().layout.clone();
                if layout.is_device() {
                    layout.device_name(0).to_owned()
                } else {
                    String::new()
                }
            };
            let handle = handle.clone();
            let stop = stop.clone();
            std::thread::Builder::new()
                .name("opcua-events".into())
                .spawn(move || {
                    procimg_opcua::events::run(
                        &instance,
                        station,
                        (tree_namespace, types_namespace),
                        handle,
                        || stop.load(Ordering::Acquire),
                    )
                })
                .context("cannot start the event thread")?
        };
        let publisher = tokio::spawn({
            let handle = handle.clone();
            async move {
                while rx.changed().await.is_ok() {
                    let snap: Arc<Snapshot> = rx.borrow_and_update().clone();
                    tree.publish(&tree_nodes, handle.subscriptions(), &snap);
                    items.notify(&snap, handle.subscriptions());
                }
                // The feed ended: the server is stopping.
                handle.cancel();
            }
        });
        tokio::spawn({
            let handle = handle.clone();
            async move {
                match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
                    Ok(mut term) => {
                        tokio::select! {
                            _ = tokio::signal::ctrl_c() => {}
                            _ = term.recv() => {}
                        }
                    }
                    Err(e) => {
                        tracing::warn!("no SIGTERM handler ({e}); Ctrl-C stops the server");
                        let _ = tokio::signal::ctrl_c().await;
                    }
                }
                handle.cancel();
            }
        });
        let listener =
            tokio::net::TcpListener::bind((options.endpoint.host.as_str(), options.endpoint.port))
                .await
                .with_context(|| format!("cannot listen on {}", options.endpoint.url()))?;
        tracing::info!(
            "serving instance {:?} at {} (PNIO items as PNIO:[CTRL{}]…)",
            options.instance,
            options.endpoint.url(),
            options.controller
        );
        let served = server.run_with(listener).await.map_err(|e| anyhow!("{e}"));
        publisher.abort();
        stop.store(true, Ordering::Release);
        let _ = events.join();
        served
    });
    stop.store(true, Ordering::Release);
    // The runtime (and with it the last sender of writes) is gone: the writer ends.
    drop(runtime);
    let _ = writer.join();
    let _ = recorder.join();
    match feeder.join() {
        Ok(Err(e)) => return Err(e.into()),
        Ok(Ok(())) => {}
        Err(_) => return Err(anyhow!("the image thread failed")),
    }
    result
}
