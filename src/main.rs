fn main() {
    println!("tamias2d");
}
