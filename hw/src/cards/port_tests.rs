//! The port backends on plain files standing in for a BAR and for /dev/port.

use super::*;

/// A plain file stands in for a BAR: one byte per register.
fn bar_file(dir: &Path, len: usize) -> PathBuf {
    let path = dir.join("resource2");
    std::fs::write(&path, vec![0u8; len]).unwrap();
    path
}

#[test]
fn sysfs_bar_reads_and_writes_one_byte_at_the_registers_offset() {
    let dir = tempfile::tempdir().unwrap();
    let path = bar_file(dir.path(), 8);
    let mut bar = SysfsBar::open(&path, 8).unwrap();
    bar.write_u8(2, 0xA5).unwrap();
    bar.write_u8(7, 0x3C).unwrap();
    assert_eq!(bar.read_u8(2).unwrap(), 0xA5);
    assert_eq!(bar.read_u8(7).unwrap(), 0x3C);
    assert_eq!(
        std::fs::read(&path).unwrap(),
        [0, 0, 0xA5, 0, 0, 0, 0, 0x3C]
    );
    let err = bar.read_u8(8).unwrap_err();
    assert!(err.to_string().contains("outside the card's 8-byte window"));
}

#[test]
fn dev_port_adds_the_base_port() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("port");
    std::fs::write(&path, vec![0u8; 0x120]).unwrap();
    let mut port = DevPortFile::new(&path).card(0x100, 16).unwrap();
    port.write_u8(0x0F, 0x90).unwrap();
    assert_eq!(std::fs::read(&path).unwrap()[0x10F], 0x90);
    assert_eq!(port.read_u8(0x0F).unwrap(), 0x90);
    assert!(port.write_u8(16, 0).is_err());
}

#[test]
fn a_second_program_cannot_open_a_card_in_use() {
    let dir = tempfile::tempdir().unwrap();
    let path = bar_file(dir.path(), 8);
    let _first = SysfsBar::open(&path, 8).unwrap();
    let Err(err) = SysfsBar::open(&path, 8) else {
        panic!("opened twice")
    };
    assert_eq!(err.kind(), io::ErrorKind::ResourceBusy);
    assert!(err.to_string().contains("in use by another program"));
}

#[test]
fn cards_through_dev_port_share_one_handle_and_a_second_program_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("port");
    std::fs::write(&path, vec![0u8; 0x400]).unwrap();
    let mut ours = DevPortFile::new(&path);
    let mut das08 = ours.card(0x100, 8).unwrap();
    let mut dda06 = ours.card(0x200, 16).unwrap();
    let mut quad04 = ours.card(0x300, 10).unwrap();
    das08.write_u8(2, 0x11).unwrap();
    dda06.write_u8(2, 0x22).unwrap();
    quad04.write_u8(2, 0x33).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(
        (bytes[0x102], bytes[0x202], bytes[0x302]),
        (0x11, 0x22, 0x33)
    );

    // Another program opens the same file independently: refused while ours is open.
    let Err(err) = DevPortFile::new(&path).card(0x100, 8) else {
        panic!("a second program opened /dev/port beside the first")
    };
    assert_eq!(err.kind(), io::ErrorKind::ResourceBusy);
    assert!(
        err.to_string().contains("in use by another program"),
        "{err}"
    );

    // The lock lives as long as any card's view does, and goes with the last one.
    drop((ours, das08, dda06));
    assert!(
        DevPortFile::new(&path).card(0, 8).is_err(),
        "the QUAD04 still holds it"
    );
    drop(quad04);
    assert!(DevPortFile::new(&path).card(0, 8).is_ok());
}

#[test]
fn counting_port_counts_reads_and_writes() {
    let dir = tempfile::tempdir().unwrap();
    let count = AccessCount::default();
    let bar = SysfsBar::open(&bar_file(dir.path(), 8), 8).unwrap();
    let mut port = CountingPort::new(bar, count.clone());
    port.write_u8(1, 1).unwrap();
    for _ in 0..3 {
        port.read_u8(0).unwrap();
    }
    assert_eq!((count.reads(), count.writes(), count.total()), (3, 1, 4));
}
