use super::*;

fn coco_one(width: u32, height: u32, segmentation: &str) -> String {
    format!(
        r#"{{"images":[{{"id":1,"file_name":"a.jpg","width":{width},"height":{height}}}],
            "annotations":[{{"image_id":1,"category_id":3,"segmentation":{segmentation},"score":0.5}}],
            "categories":[{{"id":3,"name":"Car"}}]}}"#
    )
}

fn one(text: &str) -> Silhouette {
    let frames = parse_coco(text).unwrap();
    assert_eq!(frames.len(), 1);
    assert_eq!(frames[0].silhouettes.len(), 1, "{:?}", frames[0].skipped);
    frames[0].silhouettes[0].clone()
}

fn entry_reason(r: Result<Vec<FrameMasks>, MaskError>) -> (String, &'static str) {
    match r {
        Err(MaskError::Entry { path, reason }) => (path, reason),
        other => panic!("expected Entry error, got {other:?}"),
    }
}

fn line_err(r: Result<FrameMasks, MaskError>) -> usize {
    match r {
        Err(MaskError::Line { line, .. }) => line,
        other => panic!("expected Line error, got {other:?}"),
    }
}

#[test]
fn class_names() {
    assert_eq!(
        RoadUserClass::from_name("PERSON"),
        Some(RoadUserClass::Pedestrian)
    );
    assert_eq!(
        RoadUserClass::from_name("Motorbike"),
        Some(RoadUserClass::Motorcycle)
    );
    assert_eq!(
        RoadUserClass::from_name("bicyclist"),
        Some(RoadUserClass::Cyclist)
    );
    assert_eq!(RoadUserClass::from_name("tree"), None);
    for c in RoadUserClass::ALL {
        assert_eq!(RoadUserClass::from_name(c.name()), Some(c));
    }
}

#[test]
fn hull_of_square_with_interior_and_collinear_points() {
    let pts = [
        [0.0, 0.0],
        [2.0, 1.0], // interior
        [4.0, 0.0],
        [2.0, 0.0], // on the top edge
        [4.0, 4.0],
        [4.0, 2.0], // on the right edge
        [0.0, 4.0],
        [1.0, 3.0], // interior
        [0.0, 0.0], // duplicate
        [f64::NAN, 9.0],
        [f64::INFINITY, 1.0],
    ];
    // Positive shoelace area in (x right, y down): clockwise on screen.
    assert_eq!(
        convex_hull(&pts),
        vec![[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]
    );
    assert_eq!(convex_hull(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).len(), 2);
    assert!(convex_hull(&[]).is_empty());
}

#[test]
fn rle_uncompressed_l_shape() {
    // 4 rows x 5 columns; 1-pixels (col,row): (1,0) (1,1) (1,2) (2,2) (3,2):
    //   . X . . .
    //   . X . . .
    //   . X X X .
    //   . . . . .
    // Column-major runs: col 0 = 4 zeros; col 1 = 3 ones, 1 zero; col 2 = 2 zeros,
    // 1 one, 1 zero; col 3 = 2 zeros (3 with the previous), 1 one; then 1 + 4 zeros.
    // => [4, 3, 3, 1, 3, 1, 5] (sum 20). Area 5. The outline's points are the pixel edges
    // where each row's and column's centre line leaves the mask; their hull, computed by
    // the independent Python in `compressed_rle_matches_pycocotools`'s comment:
    // (1,0.5) (1.5,0) (4,2.5) (3.5,3) (1.5,3) (1,2.5). Row 0 is used -> border.
    let s = one(&coco_one(
        5,
        4,
        r#"{"size":[4,5],"counts":[4,3,3,1,3,1,5]}"#,
    ));
    assert_eq!(s.class, RoadUserClass::Car);
    assert_eq!(s.score, Some(0.5));
    assert_eq!(
        s.hull,
        vec![
            [1.0, 0.5],
            [1.5, 0.0],
            [4.0, 2.5],
            [3.5, 3.0],
            [1.5, 3.0],
            [1.0, 2.5]
        ]
    );
    assert_eq!((s.area_px, s.parts, s.touches_border), (5.0, 1, true));

    // One interior pixel (col 2, row 2) of a 5x5 image: position 2*5+2 = 12.
    let s = one(&coco_one(5, 5, r#"{"size":[5,5],"counts":[12,1,12]}"#));
    assert_eq!(s.hull, vec![[2.0, 2.5], [2.5, 2.0], [3.0, 2.5], [2.5, 3.0]]);
    assert_eq!((s.area_px, s.touches_border), (1.0, false));

    // 3x3, a run crossing a column boundary: positions 2..=4 = (col 0,row 2),
    // (col 1,row 0), (col 1,row 1); split per column, the outline (Python, as above) is
    // (0,2.5) (1,0.5) (1.5,0) (2,0.5) (2,1.5) (0.5,3).
    let s = one(&coco_one(3, 3, r#"{"size":[3,3],"counts":[2,3,4]}"#));
    assert_eq!(
        s.hull,
        vec![
            [0.0, 2.5],
            [1.0, 0.5],
            [1.5, 0.0],
            [2.0, 0.5],
            [2.0, 1.5],
            [0.5, 3.0]
        ]
    );
    assert_eq!(s.area_px, 3.0);
}

// Vectors from pycocotools 2.0.11 (numpy 2.4.6):
//   import numpy as np, pycocotools.mask as M
//   a = np.zeros((4,5),np.uint8); a[0:3,1]=1; a[2,1:4]=1
//   b = np.zeros((40,60),np.uint8); yy,xx = np.mgrid[0:40,0:60]
//   b[((yy-20)**2+(xx-30)**2)<120]=1; b[5:9,2:50]=1; b[30:40,55:60]=1; b[0,10]=1; b[17:19,40:58]=1
//   c = np.zeros((40,60),np.uint8); c[:,3:58]=1; c[10:12,20]=0
//   M.encode(np.asfortranarray(m))['counts']
// Expected counts: run lengths of m.flatten(order='F') computed in numpy (and
// checked equal to M.decode round trip); areas from M.area; the 40x60 hull from
// a separate Python monotone chain over the outline points of M.decode(...): for each
// column with pixels (x + 0.5, top) and (x + 0.5, bottom + 1), for each row (left, y + 0.5)
// and (right + 1, y + 0.5).
// Note: pycocotools applies the delta for index > 2 (the 4th count on).
const L4X5: &str = "433N002";
const M40X60: &str = "e24T10000000000000KMUO3P10000000000000000000SO5=KA9=GB;=EB==CB?=AC?=ABa0=_OCa0=_OCa0=_OCa0=_OCa0=_OCa0=_OCa0=_OCa0=_OCa0=_OD?=AC?=AD==CD;=ED9=GE5=KDNb02^ONb02^ONb02^ONb02^ONb02^ONb02^ONb02^ONb02^ONn000000000000UO86HJ86HJ8c0000";
const M40X60_COUNTS: [u32; 184] = [
    85, 4, 36, 4, 36, 4, 36, 4, 36, 4, 36, 4, 36, 4, 36, 4, 31, 1, 4, 4, 36, 4, 36, 4, 36, 4, 36,
    4, 36, 4, 36, 4, 36, 4, 36, 4, 36, 4, 36, 4, 7, 9, 20, 4, 5, 13, 18, 4, 4, 15, 17, 4, 3, 17,
    16, 4, 2, 19, 15, 4, 2, 19, 15, 4, 1, 21, 14, 4, 1, 21, 14, 4, 1, 21, 14, 4, 1, 21, 14, 4, 1,
    21, 14, 4, 1, 21, 14, 4, 1, 21, 14, 4, 1, 21, 14, 4, 1, 21, 14, 4, 2, 19, 15, 4, 2, 19, 15, 4,
    3, 17, 16, 4, 4, 15, 17, 4, 5, 13, 18, 4, 7, 9, 20, 4, 8, 2, 26, 4, 8, 2, 26, 4, 8, 2, 26, 4,
    8, 2, 26, 4, 8, 2, 26, 4, 8, 2, 26, 4, 8, 2, 26, 4, 8, 2, 26, 4, 8, 2, 38, 2, 38, 2, 38, 2, 38,
    2, 38, 2, 38, 2, 11, 10, 17, 2, 11, 10, 17, 2, 11, 10, 30, 10, 30, 10,
];

#[test]
fn compressed_rle_matches_pycocotools() {
    assert_eq!(rle_from_string(L4X5).unwrap(), vec![4, 3, 3, 1, 3, 1, 5]);
    assert_eq!(rle_from_string(M40X60).unwrap(), M40X60_COUNTS.to_vec());
    assert_eq!(
        rle_from_string("h3be02bi0^2").unwrap(),
        vec![120, 690, 2, 1508, 80]
    );
    assert_eq!(rle_from_string("").unwrap(), Vec::<u32>::new());

    let s = one(&coco_one(
        60,
        40,
        &format!(r#"{{"size":[40,60],"counts":"{M40X60}"}}"#),
    ));
    assert_eq!((s.area_px, s.touches_border), (650.0, true));
    let expected: Vec<[f64; 2]> = vec![
        [2.0, 5.5],
        [2.5, 5.0],
        [10.5, 0.0],
        [49.5, 5.0],
        [50.0, 5.5],
        [58.0, 17.5],
        [60.0, 30.5],
        [60.0, 39.5],
        [59.5, 40.0],
        [55.5, 40.0],
        [26.5, 31.0],
        [24.5, 30.0],
        [2.5, 9.0],
        [2.0, 8.5],
    ];
    assert_eq!(s.hull, expected);

    let s = one(&coco_one(
        60,
        40,
        r#"{"size":[40,60],"counts":"h3be02bi0^2"}"#,
    ));
    assert_eq!(s.area_px, 2198.0);
    // Columns 3-57, all rows: the rectangle with its corners cut by half a pixel.
    assert_eq!(
        s.hull,
        vec![
            [3.0, 0.5],
            [3.5, 0.0],
            [57.5, 0.0],
            [58.0, 0.5],
            [58.0, 39.5],
            [57.5, 40.0],
            [3.5, 40.0],
            [3.0, 39.5]
        ]
    );
}

#[test]
fn compressed_rle_errors() {
    let reason = |s: &str| match rle_from_string(s) {
        Err(MaskError::Entry { reason, .. }) => reason,
        other => panic!("{s:?}: {other:?}"),
    };
    // 'K' = 48 + 27: 5-bit group 0b11011 with the sign bit -> -5.
    assert_eq!(reason("K"), "negative RLE count");
    // 1, 1, 1, then delta -5 on count[1] = 1 -> -4.
    assert_eq!(reason("111K"), "negative RLE count");
    // Six zero groups with "more" (48 + 32 = 'P') then 4 << 30 = 2^32.
    assert_eq!(reason("PPPPPP4"), "RLE count overflows");
    assert_eq!(reason("PPPPPPPPPPPP0"), "RLE count has too many digits");
    assert_eq!(reason("1P"), "truncated RLE string");
    assert_eq!(reason("1 "), "invalid character in RLE string");
    let many = "0".repeat(MAX_RLE_COUNTS + 1);
    assert!(matches!(
        rle_from_string(&many),
        Err(MaskError::TooLarge { .. })
    ));
}

#[test]
fn coco_dataset_classes_parts_and_order() {
    let text = r#"{"info":{},"images":[{"id":9,"file_name":"b.jpg","width":100,"height":50},{"id":2}],
      "annotations":[
        {"image_id":9,"category_id":1,"segmentation":[[10,10,20,10,20,20,10,20],[30,10,40,10,40,30]],"iscrowd":0},
        {"image_id":9,"category_id":2,"segmentation":[[0,0,5,0,5,5]]},
        {"image_id":9,"category_id":1,"segmentation":[[1,1,2,1,3,1]]},
        {"image_id":2,"category_id":1,"segmentation":[[0,0,5,0,5,5]],"score":1}],
      "categories":[{"id":1,"name":"person"},{"id":2,"name":"tree"}]}"#;
    let frames = parse_coco(text).unwrap();
    assert_eq!(
        frames.iter().map(|f| f.frame).collect::<Vec<_>>(),
        vec![9, 2]
    );
    let f = &frames[0];
    assert_eq!(
        (f.file_name.as_deref(), f.image_size),
        (Some("b.jpg"), Some([100, 50]))
    );
    assert_eq!(
        f.skipped,
        Skipped {
            unknown_class: 1,
            degenerate: 1
        }
    );
    let s = &f.silhouettes[0];
    assert_eq!(
        (s.class, s.score, s.parts),
        (RoadUserClass::Pedestrian, None, 2)
    );
    // 10x10 square + triangle of legs 10 and 20: 100 + 100 pixel centres covered. The
    // outline of those pixels, from the brute-force Python in `polygons_give_their_mask`.
    assert_eq!(s.area_px, 200.0);
    assert_eq!(
        s.hull,
        vec![
            [10.0, 10.5],
            [10.5, 10.0],
            [39.5, 10.0],
            [40.0, 10.5],
            [40.0, 28.5],
            [39.5, 29.0],
            [10.5, 20.0],
            [10.0, 19.5]
        ]
    );
    assert!(!s.touches_border);
    // Image 2 has no size: border unknown even at (0,0).
    assert_eq!(frames[1].silhouettes[0].score, Some(1.0));
    assert!(!frames[1].silhouettes[0].touches_border);
}

/// A detector's polygons traced along the pixel squares' edges, or through the boundary
/// pixels' centres (OpenCV's contours plus half a pixel, as Detectron2 writes them), give
/// the same silhouette as the RLE of the mask they were traced from, one-row ledges and
/// one-row masks included; the hull of the traced vertices would stand out. The expected outline is also what this
/// brute-force Python gives (pixels whose centre is inside or on the polygon, exact
/// fractions; then each row's and column's edge midpoints and their hull):
///
/// ```text
/// inside = lambda p, poly: on_any_edge(p, poly) or crossings_left_of(p, poly) % 2 == 1
/// mask = {(x, y) for x in range(w) for y in range(h) if inside((x + 1/2, y + 1/2), poly)}
/// ```
#[test]
fn polygons_give_their_mask() {
    // The diamond of pixels (col, row): (3,1); (2..=4,2); (1..=5,3); (2..=4,4); (3,5).
    // Column-major RLE of the 8x8 image: 11 zeros, 1, 6, 3, 4, 5, 4, 3, 6, 1, 20.
    let rle = one(&coco_one(
        8,
        8,
        r#"{"size":[8,8],"counts":[11,1,6,3,4,5,4,3,6,1,20]}"#,
    ));
    let squares = one(&coco_one(
        8,
        8,
        "[[3,1,4,1,4,2,5,2,5,3,6,3,6,4,5,4,5,5,4,5,4,6,3,6,3,5,2,5,2,4,1,4,1,3,2,3,2,2,3,2]]",
    ));
    let centres = one(&coco_one(
        8,
        8,
        "[[3.5,1.5,4.5,2.5,5.5,3.5,4.5,4.5,3.5,5.5,2.5,4.5,1.5,3.5,2.5,2.5]]",
    ));
    let diamond = vec![[1.0, 3.5], [3.5, 1.0], [6.0, 3.5], [3.5, 6.0]];
    for s in [&rle, &squares, &centres] {
        assert_eq!((&s.hull, s.area_px), (&diamond, 13.0));
    }
    // The traced vertices' own hull is the octagon through the squares' outer corners: 17
    // square pixels where the mask's outline has 12.5 (13 pixels).
    let traced = [
        [3.0, 1.0],
        [4.0, 1.0],
        [6.0, 3.0],
        [6.0, 4.0],
        [4.0, 6.0],
        [3.0, 6.0],
        [1.0, 4.0],
        [1.0, 3.0],
    ];
    let area = |h: &[[f64; 2]]| crate::road_users::polygon::signed_area(h).abs();
    assert_eq!((area(&convex_hull(&traced)), area(&diamond)), (17.0, 12.5));

    // A one-row ledge traced through the boundary pixels' centres: row 2 holds columns
    // 2..=8, row 3 columns 0..=10 (the column-major RLE of the 12x6 image). The ledge's end
    // pixels lie only on the polygon's horizontal edge, which no scan line meets.
    let rle = one(&coco_one(
        12,
        6,
        r#"{"size":[6,12],"counts":[3,1,5,1,4,2,4,2,4,2,4,2,4,2,4,2,4,2,5,1,5,1,8]}"#,
    ));
    let ledge = one(&coco_one(
        12,
        6,
        "[[2.5,2.5,8.5,2.5,9.5,3.5,10.5,3.5,0.5,3.5,1.5,3.5]]",
    ));
    assert_eq!(rle.area_px, 18.0);
    assert_eq!((&ledge.hull, ledge.area_px), (&rle.hull, rle.area_px));
    // A one-row mask (row 2, columns 3..=6) traced there and back.
    let rle = one(&coco_one(
        8,
        5,
        r#"{"size":[5,8],"counts":[17,1,4,1,4,1,4,1,7]}"#,
    ));
    let line = one(&coco_one(
        8,
        5,
        "[[3.5,2.5,4.5,2.5,5.5,2.5,6.5,2.5,5.5,2.5,4.5,2.5]]",
    ));
    assert_eq!((&line.hull, line.area_px), (&rle.hull, 4.0));
}

/// A polygon whose edges cross more scan lines than the bound is refused before any is
/// filled, whatever the image size.
#[test]
fn polygon_crossings_are_bounded() {
    let tall = "[[0,0,1,0,1,4000000,0,4000000]]";
    for text in [
        coco_one(8, 8, tall),
        format!(r#"[{{"image_id":1,"category_name":"car","segmentation":{tall}}}]"#),
    ] {
        assert!(matches!(
            parse_coco(&text),
            Err(MaskError::TooLarge { limit, .. }) if limit == crate::road_users::rasterise::MAX_CROSSINGS
        ));
    }
}

#[test]
fn coco_results_grouping() {
    let text = r#"[
      {"image_id":7,"category_name":"truck","segmentation":[[1,5,8,5,8,9]],"score":0.9},
      {"image_id":3,"category_name":"bus","segmentation":[[2,2,4,2,4,4]],"score":0.8},
      {"image_id":7,"category_name":"van","segmentation":{"size":[10,20],"counts":[12,1,187]},"score":0.7},
      {"image_id":7,"category_name":"dog","segmentation":[[2,2,4,2,4,4]],"score":0.6}]"#;
    let frames = parse_coco(text).unwrap();
    assert_eq!(
        frames.iter().map(|f| f.frame).collect::<Vec<_>>(),
        vec![7, 3]
    );
    let f = &frames[0];
    assert_eq!((f.file_name.clone(), f.image_size), (None, Some([20, 10])));
    let classes: Vec<_> = f.silhouettes.iter().map(|s| s.class).collect();
    assert_eq!(classes, vec![RoadUserClass::Truck, RoadUserClass::Van]);
    assert_eq!(f.skipped.unknown_class, 1);
    // The polygon precedes the RLE but still knows the size: y = 9 >= 10 - 1.
    assert!(f.silhouettes[0].touches_border);
    // Pixel 12 of a 10-row mask: column 1, row 2; its outline is the diamond of its edges'
    // midpoints.
    assert_eq!(
        f.silhouettes[1].hull,
        vec![[1.0, 2.5], [1.5, 2.0], [2.0, 2.5], [1.5, 3.0]]
    );
    assert_eq!(frames[1].image_size, None);
    assert!(!frames[1].silhouettes[0].touches_border);
}

#[test]
fn coco_errors() {
    assert!(matches!(
        parse_coco("{\"images\": ["),
        Err(MaskError::Json(_))
    ));
    assert_eq!(entry_reason(parse_coco("3")).0, "$");
    let bad = |seg: &str| entry_reason(parse_coco(&coco_one(5, 4, seg)));
    let (path, reason) = bad(r#"{"size":[4,5],"counts":[4,3,3]}"#);
    assert_eq!(
        (path.as_str(), reason),
        (
            "annotations[0].segmentation.counts",
            "RLE counts do not sum to height*width"
        )
    );
    assert_eq!(
        bad(r#"{"size":[5,4],"counts":[20]}"#).1,
        "RLE size differs from the image size"
    );
    assert_eq!(
        bad(r#"{"size":[0,5],"counts":[]}"#).0,
        "annotations[0].segmentation.size"
    );
    assert_eq!(
        bad(r#"{"size":[4,5],"counts":[4,-3,13]}"#).1,
        "RLE count is not a u32"
    );
    assert_eq!(
        bad(r#"{"size":[4,5],"counts":"111K"}"#).1,
        "negative RLE count"
    );
    let (path, reason) = bad("[[1,1,3,1,3,3],[1,2,3,4,5,6,7]]");
    assert_eq!(
        (path.as_str(), reason),
        (
            "annotations[0].segmentation[1]",
            "odd number of polygon coordinates"
        )
    );
    assert_eq!(bad("[[1,1,3,1]]").1, "polygon has fewer than 3 points");
    assert_eq!(
        bad(r#"[[1,1,3,1,3,"x"]]"#).1,
        "polygon coordinate is not a finite number"
    );
    assert_eq!(bad("[]").1, "empty polygon list");
    assert_eq!(bad("7").1, "not a polygon list nor an RLE object");
    assert!(matches!(parse_coco("[1e999]"), Err(MaskError::Json(_))));
    let score = coco_one(5, 4, "[[1,1,3,1,3,3]]").replace("0.5", "1.5");
    assert_eq!(entry_reason(parse_coco(&score)).0, "annotations[0].score");
    let cat = coco_one(5, 4, "[[1,1,3,1,3,3]]").replace("\"id\":3", "\"id\":4");
    assert_eq!(
        entry_reason(parse_coco(&cat)).1,
        "category_id not in categories"
    );
    let img = coco_one(5, 4, "[[1,1,3,1,3,3]]").replace("\"image_id\":1", "\"image_id\":2");
    assert_eq!(entry_reason(parse_coco(&img)).1, "image_id not in images");
    let zero = coco_one(0, 4, "[[1,1,3,1,3,3]]");
    assert_eq!(entry_reason(parse_coco(&zero)).0, "images[0].width");
    let huge = coco_one(16385, 4, "[[1,1,3,1,3,3]]");
    assert!(matches!(
        parse_coco(&huge),
        Err(MaskError::TooLarge { limit: 16384, .. })
    ));
    let results = r#"[{"image_id":1,"category_id":1,"segmentation":[[1,1,3,1,3,3]]}]"#;
    assert_eq!(entry_reason(parse_coco(results)).0, "[0].category_name");
}

#[test]
fn coco_too_many() {
    let long = coco_one(
        5,
        4,
        r#"{"size":[4,5],"counts":[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,20]}"#,
    );
    assert!(matches!(
        parse_coco(&long),
        Err(MaskError::TooLarge { limit: 21, .. })
    ));
    let images: Vec<String> = (0..=MAX_IMAGES)
        .map(|i| format!("{{\"id\":{i}}}"))
        .collect();
    let text = format!("{{\"images\":[{}]}}", images.join(","));
    assert!(matches!(
        parse_coco(&text),
        Err(MaskError::TooLarge { what: "images", .. })
    ));
    let anns = vec!["{}"; MAX_ANNOTATIONS + 1].join(",");
    assert!(matches!(
        parse_coco(&format!("[{anns}]")),
        Err(MaskError::TooLarge {
            what: "annotations",
            ..
        })
    ));
    let pts = vec!["1"; 2 * MAX_POLYGON_POINTS + 2].join(",");
    let many = coco_one(5, 4, &format!("[[{pts}]]"));
    assert!(matches!(
        parse_coco(&many),
        Err(MaskError::TooLarge {
            limit: MAX_POLYGON_POINTS,
            ..
        })
    ));
}

#[test]
fn yolo_seg_scores_normalisation_and_skips() {
    let text =
        "# header\n\n0 0.1 0.1 0.5 0.1 0.5 0.5 0.9\n2 0.1 0.1 0.5 0.1 0.5 0.5\n1 0 0 1 0 1 1\n \
                0 0.1 0.1 0.2 0.2 0.3 0.3\n2 0 0 1.0000005 0 1 1\n";
    let f = parse_yolo_seg(text, 42, [200, 100], &["car", "tree", "person"]).unwrap();
    assert_eq!((f.frame, f.image_size), (42, Some([200, 100])));
    assert_eq!(
        f.skipped,
        Skipped {
            unknown_class: 1,
            degenerate: 1
        }
    );
    let s = &f.silhouettes[0];
    assert_eq!(
        (s.class, s.score, s.parts),
        (RoadUserClass::Car, Some(0.9), 1)
    );
    // (0.1,0.1) (0.5,0.1) (0.5,0.5) scaled by 200x100 -> (20,10) (100,10) (100,50); the
    // outline of the 1600 pixels it covers (Python, as in `polygons_give_their_mask`).
    assert_eq!(
        s.hull,
        vec![
            [21.0, 10.5],
            [21.5, 10.0],
            [99.5, 10.0],
            [100.0, 10.5],
            [100.0, 49.5],
            [99.5, 50.0],
            [21.5, 11.0]
        ]
    );
    assert_eq!(s.area_px, 1600.0);
    assert!(!s.touches_border);
    assert_eq!(
        (f.silhouettes[1].class, f.silhouettes[1].score),
        (RoadUserClass::Pedestrian, None)
    );
    let s = &f.silhouettes[2];
    assert_eq!(
        s.hull,
        vec![
            [1.0, 0.5],
            [1.5, 0.0],
            [199.5, 0.0],
            [200.0, 0.5],
            [200.0, 99.5],
            [199.5, 100.0],
            [1.5, 1.0]
        ]
    );
    assert_eq!(s.area_px, 10_000.0);
    assert!(s.touches_border);
}

#[test]
fn yolo_seg_errors() {
    let names = ["car", "bus"];
    let run = |t: &str| parse_yolo_seg(t, 0, [640, 480], &names);
    assert_eq!(line_err(run("0 0 0 1 0 1 1\n\n2 0 0 1 0 1 1")), 3);
    assert_eq!(line_err(run("-1 0 0 1 0 1 1")), 1);
    assert_eq!(line_err(run("0 0 0 1 nan 1 1")), 1);
    assert_eq!(line_err(run("0 0 0 1 inf 1 1")), 1);
    assert_eq!(line_err(run("0 0 0 1 0 1 x")), 1);
    assert_eq!(line_err(run("0 0 0 1.01 0 1 1")), 1);
    assert_eq!(line_err(run("0 0 0 1 0 1 1 1.5")), 1);
    assert_eq!(line_err(run("0 0 0 1 0 0.5")), 1);
    let many = format!("0 {}", vec!["0.5"; 2 * MAX_POLYGON_POINTS + 2].join(" "));
    assert!(matches!(run(&many), Err(MaskError::TooLarge { .. })));
    assert!(matches!(
        parse_yolo_seg("", 0, [0, 480], &names),
        Err(MaskError::Entry { .. })
    ));
    assert!(matches!(
        parse_yolo_seg("", 0, [640, 20000], &names),
        Err(MaskError::TooLarge { .. })
    ));
    let err = run("5 0 0 1 0 1 1").unwrap_err();
    assert_eq!(err.to_string(), "line 1: class index out of range");
}
