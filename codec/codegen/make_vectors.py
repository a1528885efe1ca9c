#!/usr/bin/env python3
"""Make the oracle test vectors for the J2735 (2020) UPER codec.

What it makes
    codec/tests/vectors/oracle_vectors.jsonl: one JSON object a line, sorted by name:
        {"name": ..., "covers": [tags], "uper": "<lowercase hex>", "jer": {MessageFrame JER}}
    Every value is composed in this file (new values, not copied from any corpus), written
    as the X.697 JSON encoding (JER) of a MessageFrame. The bytes are NOT computed by the
    project: each JER value is encoded to UPER by pycrate (an independent ASN.1 runtime
    driven by the pycrate-compiled J2735 2020 type model in <repo>/../shared/j2735), decoded
    back by pycrate, and the vector is kept only if the decoded JER equals the composed JER
    and re-encoding it gives the same bytes. "jer" is what pycrate's to_jer() prints.

How to run (from the repository root)
    $(bash ../shared/oracle/setup.sh) codec/codegen/make_vectors.py            (write the file)
    $(bash ../shared/oracle/setup.sh) codec/codegen/make_vectors.py --check    (re-make in
        memory; exit 1 if the committed file differs)
    Paths are taken relative to this script; the shared directory is <repo>/../shared.
    Output is deterministic: no randomness (octet contents come from octets(n, seed)), keys
    sorted, one compact JSON object a line.

Coverage
    Every message of the 2020 MessageFrame set (MAP 18 ... PSM 32, TestMessage00..15 =
    240..255), minimal and rich variants, the ASN.1 construct kinds (see REQUIRED_TAGS),
    regional extensions with known (AddGrpB/AddGrpC) and unknown content, and the MAP / TIM
    geometry used by work-zone applications. The script fails if a REQUIRED_TAGS entry is not
    covered, or if a tag that names a JER key/value ("node:", "content:", "laneType:",
    "directionality:", "itis:", "msgId:") is absent from its vector. The "msg:", "partII:"
    and "opentype:" tags are also derived from the value and its bytes (and declared ones
    are checked against them).

Notes recorded here on purpose
    * Extension additions: the J2735 2020 types carry "..." extension markers but define no
      extension additions (a few appear only in 2024). No vector here has extension additions;
      none are fabricated. Extensible ENUMERATED / CHOICE / SEQUENCE values are all root
      values (the extension bit is 0); so are extensible SIZEs, except in the vectors tagged
      "bitstring:extensible-size-outside-root" (bytes still from pycrate, see below).
    * NULL and REAL: no type of the 2020 model uses them, so no vector covers them.
    * UPER length determinants: SIZE-constrained strings and lists (e.g. RTCMmessage 1..1023,
      ITIStext 1..500) encode their length as a constrained whole number (10 / 9 bits), never
      as a general length determinant. The general (1- or 2-byte) determinant appears in open
      types (MessageFrame.value, regExtValue, partII-Value). Tags: "opentype:length-2byte"
      when MessageFrame.value is 128..16383 octets, "opentype:fragmented" when it is >= 16384
      octets (16K fragment + remainder), "opentype:regext-length-2byte" for a regExtValue of
      >= 128 octets.
    * pycrate's JER quirks: an open type whose content type is unknown (regionId without a
      class-set entry) is shown as a hex string of the content octets; BIT STRINGs with an
      extensible SIZE (ExteriorLights, VehicleEventFlags, LaneAttributes-Vehicle, the PSM bit
      strings) are shown as a bare hex string, not X.697's {"value": ..., "length": ...};
      IA5String is a JSON string (control characters JSON-escaped). For such a BIT STRING
      pycrate reads a bare hex string as a value of the root size (truncating or zero-padding)
      and refuses a 0-bit value in JER, so the vectors tagged "jer:x697-bitstring-length"
      (sizes outside the root) keep X.697's {"value", "length"} form in "jer"; for those the
      check is that pycrate's output equals "jer" with that form made bare, and that the
      decoded value re-encodes to the same bytes. All other "jer" members are pycrate's own
      to_jer() output.
    * asn1tools is installed with the oracle but needs the ASN.1 text, which is SAE's
      copyrighted file and not available here, so it is not used as a second opinion.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vector_file  # noqa: E402  (beside this script)

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, '..', '..'))
SHARED = os.path.normpath(os.path.join(REPO, '..', 'shared'))
OUT = os.path.join(REPO, 'codec', 'tests', 'vectors', 'oracle_vectors.jsonl')

# Message ids of the 2020 MessageFrame set.
MAP, SPAT, BSM, CSR, EVA, ICA, NMEA, PDM, PVD, RSA, RTCM, SRM, SSM, TIM, PSM = range(18, 33)
TEST_MESSAGE_00 = 240

# Region ids of the REGION module: 1 addGrpA (no content defined in 2020), 2 addGrpB, 3 addGrpC.
ADD_GRP_A, ADD_GRP_B, ADD_GRP_C = 1, 2, 3

# A made-up work-zone site (1e-7 degree units, elevation in 10 cm).
SITE_LAT, SITE_LON, SITE_ELEV = 421234567, -837654321, 2710

REQUIRED_TAGS = [
    # messages
    'msg:MapData', 'msg:SPAT', 'msg:BasicSafetyMessage', 'msg:CommonSafetyRequest',
    'msg:EmergencyVehicleAlert', 'msg:IntersectionCollision', 'msg:NMEAcorrections',
    'msg:ProbeDataManagement', 'msg:ProbeVehicleData', 'msg:RoadSideAlert',
    'msg:RTCMcorrections', 'msg:SignalRequestMessage', 'msg:SignalStatusMessage',
    'msg:TravelerInformation', 'msg:PersonalSafetyMessage',
] + ['msg:TestMessage%02d' % i for i in range(16)] + [
    # construct kinds
    'int:min', 'int:max', 'int:negative', 'enumerated', 'enumerated:extensible',
    'choice', 'choice:extensible', 'sequence:optional-absent', 'sequence:optional-present',
    'seqof:size-1', 'seqof:upper-bound', 'bitstring:fixed', 'bitstring:extensible-size',
    'octetstring:fixed', 'octetstring:variable', 'octetstring:near-max',
    'ia5string', 'ia5string:long', 'ia5string:max-size', 'ia5string:escapes', 'boolean',
    'opentype:regional-known', 'opentype:regional-unknown', 'opentype:length-2byte',
    'opentype:regext-length-2byte', 'opentype:fragmented',
    'addgrpc:MapData', 'addgrpc:ConnectionManeuverAssist', 'addgrpc:Position3D',
    'addgrpc:IntersectionState', 'addgrpc:RestrictionUserType',
    'addgrpb:NodeOffsetPointXY', 'addgrpb:LaneDataAttribute', 'addgrpb:Position3D',
    'addgrpb:MovementEvent',
    # message variants
    'variant:minimal', 'variant:rich',
    'partII:vehicleSafetyExt', 'partII:specialVehicleExt', 'partII:supplementalVehicleExt',
    # MAP
    'node:node-XY1', 'node:node-XY2', 'node:node-XY3', 'node:node-XY4', 'node:node-XY5',
    'node:node-XY6', 'node:node-LatLon',
    'map:computed-lane', 'map:computed-offset-small', 'map:computed-offset-large',
    'map:rotateXY', 'map:scale', 'map:connectsTo', 'map:speedLimit-construction',
    'map:node-attributes', 'map:dWidth', 'map:dElevation', 'map:roadSegments',
    'map:two-intersections',
    'laneType:vehicle', 'laneType:crosswalk', 'laneType:bikeLane', 'laneType:sidewalk',
    'laneType:median', 'laneType:striping', 'laneType:trackedVehicle', 'laneType:parking',
    # TIM
    'tim:work-zone', 'content:workZone', 'content:speedLimit', 'content:advisory',
    'content:genericSign', 'content:exitService', 'itis:text',
    'itis:1025', 'itis:769', 'itis:771', 'itis:8195', 'itis:8196', 'itis:268', 'itis:8720',
    'itis:speed-number', 'tim:path-xy', 'tim:path-ll', 'tim:path-computed',
    'tim:geometry-circle', 'tim:oldRegion', 'node:node-LL1', 'node:node-LL2', 'node:node-LL3',
    'node:node-LL4', 'node:node-LL5', 'node:node-LL6',
    'directionality:forward', 'directionality:reverse', 'directionality:both',
    'tim:closedPath', 'tim:headingSlice', 'msgId:furtherInfoID', 'msgId:roadSignID',
    'tim:startYear-present', 'tim:startYear-absent', 'tim:durationTime-32000', 'tim:url',
]

# Tags whose suffix must appear in the vector's JER as a key or a scalar value.
CHECKED_TAG_PREFIXES = ('node:', 'content:', 'laneType:', 'directionality:', 'itis:', 'msgId:')

# Vectors with this tag keep X.697's {"value": hex, "length": n} for extensible-size BIT
# STRINGs in "jer" (pycrate prints a bare hex string it cannot read back at that size).
X697_BITSTRING_TAG = 'jer:x697-bitstring-length'


# ============================================================================ basic values

def frame(message_id, value):
    """A MessageFrame in JER."""
    return {'messageId': message_id, 'value': value}


def bits(size, *on):
    """A BIT STRING of `size` bits with the given bit numbers set, as pycrate's JER shows it:
    hex of the bits, first bit = most significant bit of the first octet, zero padded."""
    value = 0
    for b in on:
        assert 0 <= b < size, (b, size)
        value |= 1 << (size - 1 - b)
    nbytes = (size + 7) // 8
    value <<= nbytes * 8 - size
    return '%0*x' % (nbytes * 2, value)


def heading_slice(*sectors):
    """HeadingSlice: bit n = heading [22.5 n, 22.5 (n + 1)) degrees from north."""
    return bits(16, *sectors)


def octets(n, seed):
    """n deterministic, varied octets as lowercase hex."""
    return bytes((seed * 29 + i * 17 + (i >> 4) * 5) & 0xFF for i in range(n)).hex()


def ascii_hex(text):
    return text.encode('ascii').hex()


def ext(region_id, value):
    """A RegionalExtension (regionId + open-type content)."""
    return {'regionId': region_id, 'regExtValue': value}


def unknown_ext(region_id, nbytes, seed):
    """A RegionalExtension whose content type is not in the 2020 class set: raw octets."""
    return ext(region_id, octets(nbytes, seed))


def pos3d(lat, lon, elevation=None, regional=None):
    p = {'lat': lat, 'long': lon}
    if elevation is not None:
        p['elevation'] = elevation
    if regional is not None:
        p['regional'] = regional
    return p


def full_position(lat, lon, rich=False):
    """FullPositionVector; rich fills every optional field."""
    p = {'lat': lat, 'long': lon}
    if rich:
        p.update({
            'utcTime': {'year': 2025, 'month': 6, 'day': 17, 'hour': 14, 'minute': 32,
                        'second': 41250, 'offset': -300},
            'elevation': SITE_ELEV,
            'heading': 13500,
            'speed': {'transmisson': 'forwardGears', 'speed': 625},
            'posAccuracy': {'semiMajor': 40, 'semiMinor': 25, 'orientation': 12000},
            'timeConfidence': 'time-000-010',
            'posConfidence': {'pos': 'a1m', 'elevation': 'elev-002-00'},
            'speedConfidence': {'heading': 'prec01deg', 'speed': 'prec1ms',
                                'throttle': 'prec1percent'},
        })
    return p


def accuracy(major=40, minor=25, orientation=8000):
    return {'semiMajor': major, 'semiMinor': minor, 'orientation': orientation}


def path_history(n_points, rich=False):
    """PathHistory with n crumbs (1..23); rich adds the optional members."""
    crumbs = []
    for i in range(n_points):
        c = {'latOffset': -120 * (i + 1), 'lonOffset': 95 * (i + 1),
             'elevationOffset': (-1) ** i * i, 'timeOffset': 50 * (i + 1)}
        if rich and i % 2 == 0:
            c.update({'speed': 600 + i, 'posAccuracy': accuracy(30 + i, 20, 100 * i),
                      'heading': (i * 10) % 241})
        crumbs.append(c)
    ph = {'crumbData': crumbs}
    if rich:
        ph['initialPosition'] = full_position(SITE_LAT - 5000, SITE_LON + 4000, rich=True)
        ph['currGNSSstatus'] = bits(8, 1, 2, 6)
    return ph


def itis(code):
    return {'item': {'itis': code}}


def text(phrase):
    return {'item': {'text': phrase}}


# ============================================================================ MAP (18)

INGRESS, EGRESS, BIDIRECTIONAL = bits(2, 0), bits(2, 1), bits(2, 0, 1)
NO_SHARING = bits(10)
VEHICLE_LANE = {'vehicle': bits(8)}          # LaneAttributes-Vehicle, SIZE (8, ...)
STRAIGHT, LEFT, RIGHT = bits(12, 0), bits(12, 1), bits(12, 2)

XY_RANGE = {'node-XY1': 511, 'node-XY2': 1023, 'node-XY3': 2047, 'node-XY4': 4095,
            'node-XY5': 8191, 'node-XY6': 32767}
LL_RANGE = {'node-LL1': 2047, 'node-LL2': 8191, 'node-LL3': 32767, 'node-LL4': 131071,
            'node-LL5': 2097151, 'node-LL6': 8388607}


def node_xy(kind, x, y, attributes=None):
    n = {'delta': {kind: {'x': x, 'y': y}}}
    if attributes is not None:
        n['attributes'] = attributes
    return n


def node_latlon(lat, lon, attributes=None):
    n = {'delta': {'node-LatLon': {'lon': lon, 'lat': lat}}}
    if attributes is not None:
        n['attributes'] = attributes
    return n


def node_ll(kind, lon, lat, attributes=None):
    n = {'delta': {kind: {'lon': lon, 'lat': lat}}}
    if attributes is not None:
        n['attributes'] = attributes
    return n


def straight_nodes(count, step_cm=1500, kind='node-XY3'):
    """A lane running west from the stop line: `count` equal steps."""
    return {'nodes': [node_xy(kind, -step_cm, 0 if i else 150) for i in range(count)]}


def lane(lane_id, direction, lane_type, node_list, **optional):
    """GenericLane. Optional members by their JER names, plus sharedWith (default: none) and
    attr_regional (LaneAttributes.regional)."""
    attrs = {'directionalUse': direction, 'sharedWith': optional.pop('sharedWith', NO_SHARING),
             'laneType': lane_type}
    if 'attr_regional' in optional:
        attrs['regional'] = optional.pop('attr_regional')
    gl = {'laneID': lane_id, 'laneAttributes': attrs, 'nodeList': node_list}
    gl.update(optional)
    return gl


def intersection(iid, lanes, revision=1, ref=None, **optional):
    ig = {'id': {'id': iid}, 'revision': revision,
          'refPoint': ref or pos3d(SITE_LAT, SITE_LON), 'laneSet': lanes}
    ig.update(optional)
    return ig


def map_frame(intersections=None, revision=1, **optional):
    value = {'msgIssueRevision': revision}
    if intersections is not None:
        value['intersections'] = intersections
    value.update(optional)
    return frame(MAP, value)


def map_vectors():
    yield ('map_minimal',
           ['msg:MapData', 'variant:minimal', 'sequence:optional-absent', 'int:min'],
           map_frame(revision=0))

    yield ('map_minimal_intersection',
           ['msg:MapData', 'variant:minimal', 'seqof:size-1', 'node:node-XY1',
            'laneType:vehicle', 'bitstring:fixed', 'bitstring:extensible-size',
            'sequence:optional-absent'],
           map_frame([intersection(101, [lane(1, INGRESS, VEHICLE_LANE, {'nodes': [
               node_xy('node-XY1', 120, -300), node_xy('node-XY1', -511, 0)]})])]))

    yield ('map_rich', [
        'msg:MapData', 'variant:rich', 'sequence:optional-present', 'enumerated',
        'enumerated:extensible', 'ia5string', 'choice', 'map:connectsTo', 'map:node-attributes',
        'map:dWidth', 'map:dElevation', 'map:speedLimit-construction', 'addgrpc:MapData',
        'addgrpc:RestrictionUserType', 'addgrpc:Position3D', 'opentype:regional-known',
        'opentype:regional-unknown', 'node:node-XY2', 'node:node-XY3', 'node:node-XY4',
        'laneType:vehicle', 'laneType:crosswalk', 'laneType:median', 'bitstring:fixed',
        'bitstring:extensible-size'], map_rich())

    yield ('map_work_zone', [
        'msg:MapData', 'map:speedLimit-construction', 'map:node-attributes', 'map:dWidth',
        'map:dElevation', 'node:node-XY3', 'node:node-XY4', 'laneType:vehicle',
        'laneType:median', 'map:connectsTo'], map_work_zone())

    kinds = list(XY_RANGE) + ['node-LatLon']
    nodes = [node_xy(k, XY_RANGE[k] // 3, -XY_RANGE[k] // 5) for k in XY_RANGE]
    nodes.append(node_latlon(SITE_LAT + 1500, SITE_LON - 2500))
    yield ('map_node_offsets_all_kinds',
           ['msg:MapData', 'choice', 'choice:extensible', 'int:negative']
           + ['node:' + k for k in kinds],
           map_frame([intersection(102, [lane(1, INGRESS, VEHICLE_LANE, {'nodes': nodes})])]))

    low = [node_xy(k, -XY_RANGE[k] - 1, -XY_RANGE[k] - 1) for k in XY_RANGE]
    low.append(node_latlon(-900000000, -1799999999))
    yield ('map_node_offsets_min',
           ['msg:MapData', 'int:min', 'int:negative'] + ['node:' + k for k in kinds],
           map_frame([intersection(103, [lane(2, EGRESS, VEHICLE_LANE, {'nodes': low})])]))

    high = [node_xy(k, XY_RANGE[k], XY_RANGE[k]) for k in XY_RANGE]
    high.append(node_latlon(900000001, 1800000001))
    yield ('map_node_offsets_max',
           ['msg:MapData', 'int:max'] + ['node:' + k for k in kinds],
           map_frame([intersection(104, [lane(3, EGRESS, VEHICLE_LANE, {'nodes': high})])]))

    yield ('map_nodes_63', ['msg:MapData', 'seqof:upper-bound', 'node:node-XY2'],
           map_frame([intersection(105, [lane(4, INGRESS, VEHICLE_LANE, {'nodes': [
               node_xy('node-XY2', -(i * 37) % 1024, (i * 53) % 1024 - 512)
               for i in range(63)]})])]))

    yield ('map_lane_vehicle_attributes_outside_root', [
        'msg:MapData', 'bitstring:extensible-size-outside-root', X697_BITSTRING_TAG,
        'laneType:vehicle'],
        map_frame([intersection(106, [
            lane(1, INGRESS, {'vehicle': {'value': 'fe', 'length': 7}}, straight_nodes(2)),
            lane(2, INGRESS, {'vehicle': {'value': 'ffc0', 'length': 10}}, straight_nodes(2)),
            lane(3, INGRESS, {'vehicle': bits(8, 1)}, straight_nodes(2))])]))

    yield ('map_computed_lane_small', [
        'msg:MapData', 'map:computed-lane', 'map:computed-offset-small',
        'sequence:optional-absent', 'node:node-XY3'], map_computed_small())

    yield ('map_computed_lane_large', [
        'msg:MapData', 'map:computed-lane', 'map:computed-offset-large', 'map:rotateXY',
        'map:scale', 'int:min', 'int:max', 'int:negative', 'opentype:regional-unknown',
        'node:node-XY4'], map_computed_large())

    yield ('map_lane_types', ['msg:MapData', 'choice', 'choice:extensible', 'bitstring:fixed',
                              'bitstring:extensible-size']
           + ['laneType:' + t for t in LANE_TYPES], map_lane_types())

    yield ('map_road_segments', [
        'msg:MapData', 'map:roadSegments', 'map:speedLimit-construction', 'node:node-XY3',
        'node:node-XY5', 'laneType:vehicle', 'ia5string'], map_road_segments())

    yield ('map_two_intersections', [
        'msg:MapData', 'map:two-intersections', 'map:connectsTo', 'ia5string',
        'ia5string:max-size', 'ia5string:escapes', 'node:node-XY2', 'node:node-XY6'],
        map_two_intersections())

    yield ('map_regional_addgrpc', [
        'msg:MapData', 'addgrpc:MapData', 'addgrpc:Position3D', 'opentype:regional-known',
        'node:node-XY1', 'node:node-XY6', 'node:node-LatLon', 'seqof:size-1'],
        map_regional_addgrpc())

    yield ('map_regional_addgrpb', [
        'msg:MapData', 'addgrpb:NodeOffsetPointXY', 'addgrpb:LaneDataAttribute',
        'addgrpb:Position3D', 'opentype:regional-known', 'int:negative', 'int:min', 'int:max'],
        map_regional_addgrpb())

    yield ('map_regional_four_items', [
        'msg:MapData', 'seqof:upper-bound', 'opentype:regional-known',
        'opentype:regext-length-2byte',
        'opentype:regional-unknown', 'addgrpc:MapData'], map_regional_four_items())


def map_rich():
    nodes_in = {'nodes': [
        node_xy('node-XY3', 1200, -180, {
            'localNode': ['stopLine'],
            'enabled': ['whiteLine', 'curbOnRight'],
            'data': [{'pathEndPointAngle': -150}, {'laneCrownPointCenter': 127},
                     {'laneCrownPointLeft': -128}, {'laneCrownPointRight': 12},
                     {'laneAngle': 180},
                     {'speedLimits': [{'type': 'vehicleMaxSpeed', 'speed': 1117}]}],
            'dWidth': -40, 'dElevation': 25}),
        node_xy('node-XY4', 4095, 60, {'disabled': ['doNotBlock'], 'dWidth': 511}),
        node_xy('node-XY2', 1023, -1024, {'dElevation': -512,
                                          'regional': [unknown_ext(ADD_GRP_A, 3, 7)]}),
    ]}
    nodes_out = {'nodes': [node_xy('node-XY3', -1350, 210), node_xy('node-XY3', -2047, 0)]}
    lanes = [
        lane(1, INGRESS, {'vehicle': bits(8, 2, 7)}, nodes_in, name='EB through',
             ingressApproach=1, maneuvers=bits(12, 0, 2, 5),
             sharedWith=bits(10, 3, 4),
             connectsTo=[
                 {'connectingLane': {'lane': 5, 'maneuver': STRAIGHT},
                  'remoteIntersection': {'region': 26, 'id': 4021}, 'signalGroup': 2,
                  'userClass': 7, 'connectionID': 11},
                 {'connectingLane': {'lane': 6, 'maneuver': RIGHT}, 'signalGroup': 2}],
             overlays=[3, 9], regional=[unknown_ext(ADD_GRP_A, 4, 1)],
             attr_regional=unknown_ext(4, 2, 9)),
        lane(5, EGRESS, VEHICLE_LANE, nodes_out, egressApproach=2),
        lane(20, BIDIRECTIONAL, {'crosswalk': bits(16, 5, 6)},
             {'nodes': [node_xy('node-XY2', 900, 700), node_xy('node-XY2', 0, -1000)]}),
        lane(30, bits(2), {'median': bits(16, 1, 5, 6)},
             {'nodes': [node_xy('node-XY1', 200, 150), node_xy('node-XY3', -1800, 0)]}),
    ]
    ig = intersection(
        4020, lanes, revision=127, name='Main St & Work Zone Ave',
        ref=pos3d(SITE_LAT, SITE_LON, SITE_ELEV,
                  [ext(ADD_GRP_C, {'altitude': {'value': 27100, 'confidence': 'alt-000-50'}})]),
        laneWidth=366,
        speedLimits=[{'type': 'vehicleMaxSpeed', 'speed': 1117},
                     {'type': 'maxSpeedInConstructionZone', 'speed': 559},
                     {'type': 'vehiclesWithTrailersNightMaxSpeed', 'speed': 894}],
        preemptPriorityData=[{'zone': unknown_ext(ADD_GRP_A, 2, 3)}],
        regional=[unknown_ext(ADD_GRP_B, 5, 4)])
    ig['id']['region'] = 26
    return map_frame(
        [ig], revision=9, timeStamp=527040, layerType='intersectionData', layerID=100,
        dataParameters={'processMethod': 'survey-grade GNSS + imagery',
                        'processAgency': 'County Road Commission',
                        'lastCheckedDate': '2025-06-01', 'geoidUsed': 'GEOID18'},
        restrictionList=[{'id': 7, 'users': [
            {'basicType': 'equippedTransit'}, {'basicType': 'otherUnknownDisabilities'},
            {'regional': [ext(ADD_GRP_C, {'emission': 'typeB'}), ext(ADD_GRP_C, {})]}]}],
        regional=[ext(ADD_GRP_C, {'signalHeadLocations': [
            {'node': {'node-XY2': {'x': -850, 'y': 900}}, 'signalGroupID': 2}]})])


def map_work_zone():
    """Two westbound lanes approaching a work zone: the left lane is closed by cones."""
    closed = {'localNode': ['closedToTraffic'], 'enabled': ['taperToRight']}
    left = {'nodes': [
        node_xy('node-XY3', -250, 180),
        node_xy('node-XY4', -3000, 20, {'dWidth': -30, 'dElevation': 4}),
        node_xy('node-XY4', -2500, 0, closed),
        node_xy('node-XY4', -4000, -15, {'localNode': ['closedToTraffic'], 'dWidth': -366}),
    ]}
    right = {'nodes': [
        node_xy('node-XY3', -250, -180),
        node_xy('node-XY4', -3000, 20, {'dElevation': 4}),
        node_xy('node-XY4', -2500, 0,
                {'data': [{'speedLimits': [{'type': 'maxSpeedInConstructionZone',
                                            'speed': 139}]}]}),
        node_xy('node-XY4', -4000, -15),
    ]}
    lanes = [
        lane(1, INGRESS, VEHICLE_LANE, left, maneuvers=bits(12, 0, 6),
             connectsTo=[{'connectingLane': {'lane': 11, 'maneuver': STRAIGHT}}]),
        lane(2, INGRESS, VEHICLE_LANE, right, maneuvers=bits(12, 0),
             connectsTo=[{'connectingLane': {'lane': 12, 'maneuver': STRAIGHT}}]),
        lane(3, bits(2), {'median': bits(16, 5, 6)},
             {'nodes': [node_xy('node-XY3', -250, 0), node_xy('node-XY4', -4095, 0)]}),
    ]
    return map_frame([intersection(
        7001, lanes, revision=3, ref=pos3d(SITE_LAT, SITE_LON, SITE_ELEV), laneWidth=366,
        speedLimits=[{'type': 'vehicleMaxSpeed', 'speed': 556},
                     {'type': 'maxSpeedInConstructionZone', 'speed': 139}])],
        revision=3, timeStamp=241200, layerType='roadwaySectionData')


def map_computed_small():
    lanes = [
        lane(1, INGRESS, VEHICLE_LANE, straight_nodes(3)),
        lane(2, INGRESS, VEHICLE_LANE, {'computed': {
            'referenceLaneId': 1, 'offsetXaxis': {'small': 0},
            'offsetYaxis': {'small': -366}}}),
    ]
    return map_frame([intersection(110, lanes)])


def map_computed_large():
    lanes = [
        lane(1, EGRESS, VEHICLE_LANE, straight_nodes(2, 4000, 'node-XY4')),
        lane(2, EGRESS, VEHICLE_LANE, {'computed': {
            'referenceLaneId': 1, 'offsetXaxis': {'large': -32767},
            'offsetYaxis': {'large': 32767}, 'rotateXY': 28800,
            'scaleXaxis': -2048, 'scaleYaxis': 2047,
            'regional': [unknown_ext(ADD_GRP_A, 1, 5)]}}),
        lane(3, EGRESS, VEHICLE_LANE, {'computed': {
            'referenceLaneId': 1, 'offsetXaxis': {'small': 2047},
            'offsetYaxis': {'large': -2048}, 'rotateXY': 0, 'scaleXaxis': 0}}),
    ]
    return map_frame([intersection(111, lanes)])


LANE_TYPES = {
    'vehicle': bits(8, 0, 3),
    'crosswalk': bits(16, 1, 5, 6),
    'bikeLane': bits(16, 1, 5),
    'sidewalk': bits(16, 1, 3),
    'median': bits(16, 1, 6),
    'striping': bits(16, 1, 2),
    'trackedVehicle': bits(16, 2),
    'parking': bits(16, 1, 3),
}


def map_lane_types():
    lanes = [lane(i + 1, bits(2, i % 2), {kind: value},
                  {'nodes': [node_xy('node-XY2', -100 * i, 300 * (i % 3)),
                             node_xy('node-XY3', -1500, 10 * i)]})
             for i, (kind, value) in enumerate(LANE_TYPES.items())]
    return map_frame([intersection(120, lanes)])


def map_road_segments():
    def segment(sid, ref_lat, lanes, **optional):
        seg = {'id': {'region': 26, 'id': sid}, 'revision': 4,
               'refPoint': pos3d(ref_lat, SITE_LON - 30000, SITE_ELEV), 'roadLaneSet': lanes}
        seg.update(optional)
        return seg
    seg1 = segment(3301, SITE_LAT + 20000, [
        lane(1, EGRESS, VEHICLE_LANE, straight_nodes(4, 3500, 'node-XY4')),
        lane(2, INGRESS, VEHICLE_LANE, {'nodes': [
            node_xy('node-XY5', 8000, 366), node_xy('node-XY5', 8191, -8192)]}),
    ], name='Route 9 EB km 12', laneWidth=350,
        speedLimits=[{'type': 'maxSpeedInConstructionZone', 'speed': 695}],
        regional=[unknown_ext(ADD_GRP_B, 2, 8)])
    seg2 = segment(3302, SITE_LAT + 21000, [
        lane(1, EGRESS, VEHICLE_LANE, straight_nodes(2, 2000))])
    seg2['id'].pop('region')
    return map_frame(revision=4, layerType='roadwaySectionData', roadSegments=[seg1, seg2])


def map_two_intersections():
    base = 'Elm "North" \\ 5th\tSt: lanes closed '
    name63 = base + '-' * (63 - len(base))      # DescriptiveName at its SIZE upper bound
    first = intersection(201, [
        lane(1, INGRESS, VEHICLE_LANE, straight_nodes(2, 900, 'node-XY2'),
             connectsTo=[{'connectingLane': {'lane': 3, 'maneuver': LEFT},
                          'remoteIntersection': {'id': 202}}]),
    ], name=name63)
    second = intersection(202, [
        lane(3, EGRESS, VEHICLE_LANE, {'nodes': [
            node_xy('node-XY6', -30000, 32767), node_xy('node-XY6', -32768, -1)]}),
    ], revision=2, ref=pos3d(SITE_LAT + 3000, SITE_LON - 40000))
    return map_frame([first, second], revision=12)


def map_regional_addgrpc():
    heads = [{'node': {'node-XY1': {'x': -512, 'y': 511}}, 'signalGroupID': 0},
             {'node': {'node-XY6': {'x': 32767, 'y': -32768}}, 'signalGroupID': 255},
             {'node': {'node-LatLon': {'lon': SITE_LON + 77, 'lat': SITE_LAT - 66}},
              'signalGroupID': 4}]
    ref = pos3d(SITE_LAT, SITE_LON, SITE_ELEV,
                [ext(ADD_GRP_C, {'altitude': {'value': -100000, 'confidence': 'unavailable'}})])
    return map_frame([intersection(130, [lane(1, INGRESS, VEHICLE_LANE, straight_nodes(2))],
                                   ref=ref)],
                     regional=[ext(ADD_GRP_C, {'signalHeadLocations': heads})])


def map_regional_addgrpb():
    dms = {'latitude': {'d': -90, 'm': 0, 's': 0}, 'longitude': {'d': 180, 'm': 59, 's': 5999},
           'elevation': -32768}
    nodes = {'nodes': [
        node_xy('node-XY3', 700, 200, {'data': [{'regional': [ext(ADD_GRP_B, {})]}]}),
        {'delta': {'regional': ext(ADD_GRP_B, {'posA': {'lon': -64800000, 'lat': 32400000}})}},
        {'delta': {'regional': ext(ADD_GRP_B, {'posB': {
            'lon': {'d': -83, 'm': 45, 's': 3555}, 'lat': {'d': 42, 'm': 7, 's': 2444}}})}},
    ]}
    ref = pos3d(SITE_LAT, SITE_LON, regional=[ext(ADD_GRP_B, dms)])
    return map_frame([intersection(131, [lane(1, INGRESS, VEHICLE_LANE, nodes)], ref=ref)])


def map_regional_four_items():
    return map_frame(revision=77, regional=[
        ext(ADD_GRP_C, {}),
        unknown_ext(ADD_GRP_A, 6, 11),
        unknown_ext(ADD_GRP_B, 1, 12),    # addGrpB has no MapData content: unknown here
        unknown_ext(200, 130, 13),        # 130 octets: 2-byte length of regExtValue
    ])


# ============================================================================ TIM (31)

WORK_ZONE, LANE_CLOSED, LANE_CLOSED_AHEAD = 1025, 769, 771
LEFT_LANE, RIGHT_LANE, SPEED_LIMIT, MPH, WORKERS = 8195, 8196, 268, 8720, 6952


def speed_itis(mph):
    """ITIS 'numbers' group: 12544 + N."""
    return 12544 + mph


def xy_path(nodes, scale=None):
    p = {'offset': {'xy': {'nodes': nodes}}}
    if scale is not None:
        p['scale'] = scale
    return {'path': p}


def ll_path(nodes, scale=None):
    p = {'offset': {'ll': {'nodes': nodes}}}
    if scale is not None:
        p['scale'] = scale
    return {'path': p}


def data_frame(content, regions, msg_id=None, start_time=241200, duration=60, priority=5,
               frame_type='advisory', start_year=2025, url=None):
    df = {'notUsed': 0, 'frameType': frame_type,
          'msgId': msg_id or {'furtherInfoID': 'a55a'},
          'startTime': start_time, 'durationTime': duration, 'priority': priority,
          'notUsed1': 0, 'regions': regions, 'notUsed2': 0, 'notUsed3': 0, 'content': content}
    if start_year is not None:
        df['startYear'] = start_year
    if url is not None:
        df['url'] = url
    return df


def road_sign(lat=SITE_LAT, lon=SITE_LON, view=heading_slice(4, 5), mutcd=None, crc=None,
              elevation=None):
    rs = {'position': pos3d(lat, lon, elevation), 'viewAngle': view}
    if mutcd is not None:
        rs['mutcdCode'] = mutcd
    if crc is not None:
        rs['crc'] = crc
    return {'roadSignID': rs}


def tim_frame(frames, msg_cnt=1, **optional):
    value = {'msgCnt': msg_cnt, 'dataFrames': frames}
    value.update(optional)
    return frame(TIM, value)


def wz_region(description, **more):
    """A region along a closed lane: anchor = work-zone start, path along the centreline."""
    r = {'name': 'WZ lane 1', 'id': {'region': 26, 'id': 3301},
         'anchor': pos3d(SITE_LAT, SITE_LON, SITE_ELEV), 'laneWidth': 366,
         'directionality': 'forward', 'closedPath': False, 'direction': heading_slice(11, 12),
         'description': description}
    r.update(more)
    return r


def tim_vectors():
    yield ('tim_minimal', ['msg:TravelerInformation', 'variant:minimal', 'seqof:size-1',
                           'sequence:optional-absent', 'msgId:furtherInfoID',
                           'content:advisory', 'tim:startYear-absent', 'octetstring:fixed',
                           'int:min'],
           tim_frame([data_frame({'advisory': [itis(0)]}, [{}], start_time=0, duration=0,
                                 priority=0, start_year=None, frame_type='unknown',
                                 msg_id={'furtherInfoID': '0000'})], msg_cnt=0))

    yield ('tim_rich', [
        'msg:TravelerInformation', 'variant:rich', 'sequence:optional-present',
        'msgId:roadSignID', 'tim:startYear-present', 'tim:url', 'tim:path-xy', 'tim:closedPath',
        'tim:headingSlice', 'directionality:forward', 'octetstring:fixed', 'ia5string',
        'opentype:regional-unknown', 'opentype:regional-known', 'addgrpc:Position3D',
        'addgrpb:Position3D', 'boolean', 'content:workZone', 'itis:text', 'itis:1025',
        'node:node-XY2', 'node:node-XY3', 'map:node-attributes', 'map:dWidth',
        'map:dElevation', 'int:max', 'enumerated:extensible'],
        tim_rich())

    yield ('tim_work_zone_left_lane_closed', [
        'msg:TravelerInformation', 'tim:work-zone', 'content:workZone', 'content:speedLimit',
        'itis:1025', 'itis:769', 'itis:8195', 'itis:268', 'itis:8720', 'itis:speed-number',
        'tim:path-xy', 'node:node-XY3', 'node:node-XY4', 'msgId:roadSignID',
        'directionality:forward', 'tim:headingSlice'], tim_work_zone_left())

    yield ('tim_work_zone_right_lane_closed_ahead', [
        'msg:TravelerInformation', 'tim:work-zone', 'content:workZone', 'content:speedLimit',
        'itis:1025', 'itis:771', 'itis:8196', 'itis:268', 'itis:8720', 'itis:speed-number',
        'itis:text', 'tim:path-ll', 'node:node-LL1', 'node:node-LL2', 'msgId:furtherInfoID',
        'directionality:forward'], tim_work_zone_right())

    yield ('tim_work_zone_speed_text', [
        'msg:TravelerInformation', 'tim:work-zone', 'content:workZone', 'content:speedLimit',
        'itis:1025', 'itis:text', 'itis:268', 'tim:path-xy', 'node:node-LatLon',
        'node:node-XY5', 'directionality:both', 'tim:durationTime-32000'],
        tim_work_zone_speed_text())

    yield ('tim_path_xy_all_node_kinds', [
        'msg:TravelerInformation', 'tim:path-xy', 'choice:extensible', 'int:negative']
        + ['node:' + k for k in list(XY_RANGE) + ['node-LatLon']], tim_path_xy_all())

    yield ('tim_path_ll_all_node_kinds', [
        'msg:TravelerInformation', 'tim:path-ll', 'int:negative', 'int:min', 'int:max']
        + ['node:' + k for k in list(LL_RANGE) + ['node-LatLon']], tim_path_ll_all())

    yield ('tim_path_computed_lane', [
        'msg:TravelerInformation', 'tim:path-computed', 'map:computed-lane',
        'map:computed-offset-small', 'map:computed-offset-large', 'map:rotateXY', 'map:scale',
        'directionality:reverse'], tim_path_computed())

    yield ('tim_geometry_circle', [
        'msg:TravelerInformation', 'tim:geometry-circle', 'enumerated',
        'opentype:regional-unknown', 'directionality:both'], tim_geometry_circle())

    yield ('tim_old_region_variants', [
        'msg:TravelerInformation', 'tim:oldRegion', 'choice', 'node:node-XY1',
        'sequence:optional-absent', 'sequence:optional-present'], tim_old_region())

    yield ('tim_directionality_variants', [
        'msg:TravelerInformation', 'directionality:forward', 'directionality:reverse',
        'directionality:both', 'tim:closedPath', 'tim:headingSlice', 'boolean', 'enumerated'],
        tim_directionality())

    yield ('tim_regions_16', ['msg:TravelerInformation', 'seqof:upper-bound', 'tim:path-ll',
                              'node:node-LL3', 'node:node-LL4'], tim_regions_16())

    yield ('tim_data_frames_8', [
        'msg:TravelerInformation', 'seqof:upper-bound', 'content:advisory', 'content:workZone',
        'content:genericSign', 'content:speedLimit', 'content:exitService', 'enumerated',
        'enumerated:extensible', 'msgId:furtherInfoID', 'msgId:roadSignID'],
        tim_data_frames_8())

    yield ('tim_road_sign_mutcd_crc', [
        'msg:TravelerInformation', 'msgId:roadSignID', 'octetstring:fixed',
        'tim:startYear-present', 'tim:durationTime-32000', 'int:max'], tim_road_sign())

    yield ('tim_cancel_zero_duration', [
        'msg:TravelerInformation', 'tim:work-zone', 'content:workZone', 'itis:1025',
        'tim:startYear-absent', 'int:min', 'msgId:furtherInfoID'], tim_cancel())

    yield ('tim_url_fields_max', ['msg:TravelerInformation', 'tim:url', 'ia5string',
                                  'ia5string:max-size'], tim_urls())

    yield ('tim_advisory_long_text', [
        'msg:TravelerInformation', 'content:advisory', 'itis:text', 'ia5string',
        'ia5string:long', 'ia5string:max-size'], tim_long_text())

    yield ('tim_advisory_fragmented', [
        'msg:TravelerInformation', 'content:advisory', 'itis:text', 'ia5string:long',
        'opentype:fragmented'], tim_fragmented())


def tim_rich():
    path = xy_path([
        node_xy('node-XY3', -1500, 30, {'localNode': ['closedToTraffic'], 'dWidth': -366,
                                         'dElevation': 3}),
        node_xy('node-XY2', -1000, 0, {'enabled': ['taperToRight'],
                                        'data': [{'laneAngle': -20}]}),
    ], scale=0)
    anchor = pos3d(SITE_LAT, SITE_LON, SITE_ELEV, [
        ext(ADD_GRP_B, {'latitude': {'d': 42, 'm': 7, 's': 2444},
                        'longitude': {'d': -83, 'm': 45, 's': 3555}, 'elevation': 271}),
        ext(ADD_GRP_C, {'altitude': {'value': 27100, 'confidence': 'alt-000-20'}})])
    region = wz_region(path, anchor=anchor, closedPath=True,
                       regional=[unknown_ext(ADD_GRP_A, 2, 21)])
    df = data_frame({'workZone': [itis(WORK_ZONE), itis(LANE_CLOSED), itis(LEFT_LANE),
                                  text('Use right lane'), itis(WORKERS)]},
                    [region], msg_id=road_sign(mutcd='warning', crc='beef', elevation=SITE_ELEV),
                    start_time=527040, duration=32000, priority=7, start_year=4095,
                    url='wz/1234')
    return tim_frame([df], msg_cnt=127, timeStamp=527040, packetID='0a1b2c3d4e5f607182',
                     urlB='https://example.org/tim/', regional=[unknown_ext(ADD_GRP_C, 3, 22)])


def tim_work_zone_left():
    path = xy_path([node_xy('node-XY3', -120, 40), node_xy('node-XY4', -3100, 25),
                    node_xy('node-XY4', -2950, -10)])
    packet = '5a0c0e11000000002a'
    wz = data_frame({'workZone': [itis(WORK_ZONE), itis(LANE_CLOSED), itis(LEFT_LANE)]},
                    [wz_region(path)], msg_id=road_sign(mutcd='warning'))
    sl = data_frame({'speedLimit': [itis(SPEED_LIMIT), itis(speed_itis(25)), itis(MPH)]},
                    [wz_region(path, name='WZ speed')], msg_id=road_sign(mutcd='regulatory'),
                    frame_type='roadSignage')
    return tim_frame([wz, sl], msg_cnt=12, timeStamp=241230, packetID=packet)


def tim_work_zone_right():
    path = ll_path([node_ll('node-LL1', -1800, 20), node_ll('node-LL2', -6400, -150),
                    node_ll('node-LL2', -8191, 8191)])
    region = wz_region(path, name='WZ lane 2', laneWidth=350)
    wz = data_frame({'workZone': [itis(WORK_ZONE), itis(LANE_CLOSED_AHEAD), itis(RIGHT_LANE),
                                  text('MERGE LEFT')]}, [region])
    sl = data_frame({'speedLimit': [itis(SPEED_LIMIT), itis(speed_itis(35)), itis(MPH)]},
                    [region])
    return tim_frame([wz, sl], msg_cnt=13, packetID='5a0c0e11000000002b')


def tim_work_zone_speed_text():
    path = xy_path([node_latlon(SITE_LAT + 10, SITE_LON - 20), node_xy('node-XY5', -8000, 50),
                    node_xy('node-XY5', -6000, -40)], scale=2)
    region = wz_region(path, directionality='both', closedPath=False)
    wz = data_frame({'workZone': [itis(WORK_ZONE), text('SHOULDER WORK'), itis(WORKERS)]},
                    [region], duration=32000)
    sl = data_frame({'speedLimit': [itis(SPEED_LIMIT), text('25'), text('MPH')]}, [region],
                    duration=32000)
    return tim_frame([wz, sl], msg_cnt=5, packetID='5a0c0e11000000002c')


def tim_path_xy_all():
    nodes = [node_xy(k, -(XY_RANGE[k] // 2), XY_RANGE[k] // 7) for k in XY_RANGE]
    nodes.insert(3, node_latlon(SITE_LAT - 700, SITE_LON - 9000))
    return tim_frame([data_frame({'advisory': [itis(WORK_ZONE)]},
                                 [wz_region(xy_path(nodes, scale=15))])])


def tim_path_ll_all():
    nodes = [node_ll(k, -LL_RANGE[k] - 1, LL_RANGE[k]) for k in LL_RANGE]
    nodes.append(node_latlon(SITE_LAT + 25000, SITE_LON + 25000))
    nodes.append(node_ll('node-LL1', 3, -4, {
        'localNode': ['mergePoint'], 'disabled': ['rumbleStripPresent'],
        'enabled': ['taperToCenterLine', 'unEvenPavementPresent'],
        'data': [{'laneCrownPointCenter': -5}], 'dWidth': 50, 'dElevation': -10,
        'regional': [unknown_ext(ADD_GRP_A, 1, 31)]}))
    return tim_frame([data_frame({'advisory': [itis(WORK_ZONE)]},
                                 [wz_region(ll_path(nodes, scale=1))])])


def tim_path_computed():
    regions = [
        wz_region({'path': {'offset': {'xy': {'computed': {
            'referenceLaneId': 2, 'offsetXaxis': {'small': -366},
            'offsetYaxis': {'large': 4000}, 'rotateXY': 14400, 'scaleXaxis': 100,
            'scaleYaxis': -100}}}}}, directionality='reverse'),
        wz_region({'path': {'scale': 3, 'offset': {'xy': {'computed': {
            'referenceLaneId': 0, 'offsetXaxis': {'large': 12000},
            'offsetYaxis': {'small': 0}}}}}}, name='WZ lane 0'),
    ]
    return tim_frame([data_frame({'advisory': [itis(WORK_ZONE)]}, regions)])


def tim_geometry_circle():
    geometry = {'geometry': {
        'direction': heading_slice(*range(16)), 'extent': 'useFor500meters', 'laneWidth': 700,
        'circle': {'center': pos3d(SITE_LAT, SITE_LON, SITE_ELEV), 'radius': 4095,
                   'units': 'decimeter'},
        'regional': [unknown_ext(ADD_GRP_C, 2, 41)]}}
    small = {'geometry': {'direction': heading_slice(0), 'extent': 'forever',
                          'circle': {'center': pos3d(SITE_LAT, SITE_LON), 'radius': 0,
                                     'units': 'mile'}}}
    return tim_frame([data_frame({'advisory': [itis(WORKERS)]}, [
        {'anchor': pos3d(SITE_LAT, SITE_LON), 'directionality': 'both',
         'description': geometry},
        {'description': small}])])


def tim_old_region():
    shape = {'oldRegion': {'direction': heading_slice(3), 'extent': 'useFor1000meters',
                           'area': {'shapePointSet': {
                               'anchor': pos3d(SITE_LAT, SITE_LON), 'laneWidth': 366,
                               'directionality': 'forward',
                               'nodeList': {'nodes': [node_xy('node-XY1', 10, 20),
                                                      node_xy('node-XY1', -30, 40)]}}}}}
    shape_min = {'oldRegion': {'direction': heading_slice(), 'extent': 'useInstantlyOnly',
                               'area': {'shapePointSet': {'nodeList': {'computed': {
                                   'referenceLaneId': 1, 'offsetXaxis': {'small': 1},
                                   'offsetYaxis': {'small': -1}}}}}}}
    circle = {'oldRegion': {'direction': heading_slice(15), 'extent': 'useFor10meters',
                            'area': {'circle': {'center': pos3d(SITE_LAT, SITE_LON, -4096),
                                                'radius': 120, 'units': 'meter'}}}}
    points = {'oldRegion': {'direction': heading_slice(7, 8), 'extent': 'useFor100meters',
                            'area': {'regionPointSet': {
                                'anchor': pos3d(SITE_LAT, SITE_LON, 61439), 'scale': 4,
                                'nodeList': [{'xOffset': -32768, 'yOffset': 32767},
                                             {'xOffset': 100, 'yOffset': -200,
                                              'zOffset': 5}]}}}}
    points_min = {'oldRegion': {'direction': heading_slice(1), 'extent': 'useFor50meters',
                                'area': {'regionPointSet': {'nodeList': [
                                    {'xOffset': 0, 'yOffset': 0}]}}}}
    regions = [{'description': d} for d in (shape, shape_min, circle, points, points_min)]
    return tim_frame([data_frame({'advisory': [itis(WORK_ZONE)]}, regions)])


def tim_directionality():
    path = xy_path([node_xy('node-XY2', -900, 0), node_xy('node-XY2', -900, 0)])
    regions = []
    for i, way in enumerate(['unavailable', 'forward', 'reverse', 'both']):
        regions.append({'anchor': pos3d(SITE_LAT + i * 350, SITE_LON), 'directionality': way,
                        'closedPath': bool(i % 2), 'direction': heading_slice(4 * i, 4 * i + 1),
                        'description': path})
    regions.append({'closedPath': True})
    return tim_frame([data_frame({'advisory': [itis(WORK_ZONE)]}, regions)])


def tim_regions_16():
    regions = []
    for i in range(16):
        kind = 'node-LL3' if i % 2 else 'node-LL4'
        regions.append({'anchor': pos3d(SITE_LAT + 100 * i, SITE_LON - 100 * i),
                        'description': ll_path([node_ll(kind, -20000 - i, 150 * i),
                                                node_ll(kind, -20000, -150 * i)])})
    return tim_frame([data_frame({'workZone': [itis(WORK_ZONE)]}, regions)])


def tim_data_frames_8():
    contents = [
        {'advisory': [itis(WORK_ZONE), text('Expect delays')]},
        {'workZone': [itis(WORK_ZONE), itis(LANE_CLOSED), itis(LEFT_LANE)]},
        {'genericSign': [itis(7186), text('DETOUR')]},
        {'speedLimit': [itis(SPEED_LIMIT), itis(speed_itis(45)), itis(MPH)]},
        {'exitService': [itis(11794), text('EXIT 12')]},
        {'workZone': [text('X' * 16)] * 16},
        {'advisory': [itis(65535)]},
        {'exitService': [itis(1)]},
    ]
    types = ['unknown', 'advisory', 'roadSignage', 'commercialSignage']
    frames = []
    for i, content in enumerate(contents):
        msg_id = road_sign(view=heading_slice(i)) if i % 2 else {'furtherInfoID': '%04x' % i}
        frames.append(data_frame(content, [{'anchor': pos3d(SITE_LAT, SITE_LON + i)}],
                                 msg_id=msg_id, frame_type=types[i % 4], priority=i % 8,
                                 start_time=241200 + i, duration=15 * i,
                                 start_year=None if i % 3 == 0 else 2025))
    return tim_frame(frames, msg_cnt=64)


def tim_road_sign():
    df = data_frame({'genericSign': [itis(WORK_ZONE)]}, [{'name': 'Sign A'}],
                    msg_id=road_sign(900000001, 1800000001, heading_slice(*range(16)),
                                     mutcd='rec', crc='ffff', elevation=61439),
                    duration=32000, start_year=2025)
    return tim_frame([df], msg_cnt=2)


def tim_cancel():
    df = data_frame({'workZone': [itis(WORK_ZONE)]}, [wz_region(xy_path([
        node_xy('node-XY3', -1500, 0), node_xy('node-XY3', -1500, 0)]))],
        duration=0, start_year=None)
    return tim_frame([df], msg_cnt=14, packetID='5a0c0e11000000002a')


def tim_urls():
    url_base = 'https://v2x.example.org/traveler-info/wz/'
    url_base += 'a' * (45 - len(url_base))    # URL-Base at its SIZE upper bound
    df = data_frame({'advisory': [itis(WORK_ZONE)]}, [{}], url='zone/2025/00042')
    assert len(df['url']) == 15
    return tim_frame([df], urlB=url_base)


def tim_long_text():
    sentence = ('Road work ahead on Route 9 eastbound between exits 11 and 12; left lane '
                'closed; expect delays of up to fifteen minutes during peak hours. ')
    long200 = (sentence * 2)[:200]
    long500 = (sentence * 4)[:500]
    return tim_frame([data_frame({'advisory': [itis(WORK_ZONE), text(long200),
                                               text(long500)]}, [{}])])


def tim_fragmented():
    """An advisory long enough that MessageFrame.value exceeds 16 K octets."""
    items = [text(('Segment %02d: ' % i + 'lane closed, merge left, workers present. ' * 12)
                  [:500]) for i in range(40)]
    return tim_frame([data_frame({'advisory': items}, [{}])])


# ============================================================================ BSM (20)

def bsm_core(**overrides):
    core = {'msgCnt': 17, 'id': '1a2b3c4d', 'secMark': 41250, 'lat': SITE_LAT + 900,
            'long': SITE_LON - 1200, 'elev': SITE_ELEV,
            'accuracy': accuracy(), 'transmission': 'forwardGears', 'speed': 556,
            'heading': 27000, 'angle': 3,
            'accelSet': {'long': -35, 'lat': 12, 'vert': 0, 'yaw': -150},
            'brakes': {'wheelBrakes': bits(5), 'traction': 'off', 'abs': 'on', 'scs': 'on',
                       'brakeBoost': 'off', 'auxBrakes': 'unavailable'},
            'size': {'width': 185, 'length': 480}}
    core.update(overrides)
    return core


def bsm_frame(core, part2=None, regional=None):
    value = {'coreData': core}
    if part2 is not None:
        value['partII'] = part2
    if regional is not None:
        value['regional'] = regional
    return frame(BSM, value)


def vehicle_safety_ext(rich=True, crumbs=4):
    ext0 = {'events': bits(13, 0, 7)}
    if rich:
        ext0.update({'pathHistory': path_history(crumbs, rich=True),
                     'pathPrediction': {'radiusOfCurve': -32767, 'confidence': 200},
                     'lights': bits(9, 0, 3, 8)})
    return {'partII-Id': 0, 'partII-Value': ext0}


def special_vehicle_ext():
    pivot = {'pivotOffset': -1024, 'pivotAngle': 28800, 'pivots': True}
    unit = {'isDolly': False, 'width': 250, 'length': 1200, 'height': 127, 'mass': 255,
            'bumperHeights': {'front': 0, 'rear': 127}, 'centerOfGravity': 60,
            'frontPivot': pivot, 'rearPivot': {'pivotOffset': 1023, 'pivotAngle': 0,
                                                 'pivots': False},
            'rearWheelOffset': -2048, 'positionOffset': {'x': -1300, 'y': 0},
            'elevationOffset': -64,
            'crumbData': [{'pivotAngle': 100, 'timeOffset': 1,
                           'positionOffset': {'x': -1, 'y': 2}, 'elevationOffset': 63,
                           'heading': 240},
                          {'pivotAngle': 200, 'timeOffset': 65535,
                           'positionOffset': {'x': 2047, 'y': -2048}}]}
    dolly = {'isDolly': True, 'width': 0, 'length': 0, 'frontPivot': pivot,
             'positionOffset': {'x': 0, 'y': 0}}
    return {'partII-Id': 1, 'partII-Value': {
        'vehicleAlerts': {'notUsed': 0, 'sirenUse': 'notInUse',
                          'lightsUse': 'arrowSignsActive', 'multi': 'singleVehicle',
                          'events': {'notUsed': 0, 'event': bits(16, 4)},
                          'responseType': 'slowMoving'},
        'description': {'typeEvent': WORK_ZONE, 'description': [LANE_CLOSED, LEFT_LANE],
                        'priority': '07', 'heading': heading_slice(12), 'extent':
                        'useFor500meters', 'regional': [unknown_ext(ADD_GRP_A, 2, 51)]},
        'trailers': {'notUsed': 0, 'connection': pivot, 'units': [unit, dolly]}}}


def supplemental_vehicle_ext():
    return {'partII-Id': 2, 'partII-Value': {
        'classification': 77,
        'classDetails': {'keyType': 255, 'role': 'roadWork', 'iso3883': 100,
                         'hpmsType': 'axleCnt2', 'vehicleType': 'maintenance-vehicles',
                         'responseEquip': 'flatbed-tow', 'responderType':
                         'transportation-response-units', 'fuelType': 15,
                         'regional': [unknown_ext(ADD_GRP_B, 1, 52)]},
        'vehicleData': {'height': 70, 'bumpers': {'front': 40, 'rear': 45}, 'mass': 180,
                        'trailerWeight': 64255},
        'weatherReport': {'isRaining': 'precip', 'rainRate': 65535,
                          'precipSituation': 'rainModerate', 'solarRadiation': 0,
                          'friction': 101, 'roadFriction': 50},
        'weatherProbe': {'airTemp': 191, 'airPressure': 0,
                         'rainRates': {'statusFront': 'intermittent', 'rateFront': 12,
                                       'statusRear': 'automaticPresent', 'rateRear': 127}},
        'obstacle': {'obDist': 32767, 'obDirect': 28800, 'description': 541,
                     'locationDetails': 'in-road-construction-area',
                     'dateTime': {'year': 2025, 'month': 12, 'day': 31, 'hour': 23,
                                  'minute': 60, 'second': 60999, 'offset': 840},
                     'vertEvent': bits(5, 1, 4)},
        'status': {'statusDetails': 523, 'locationDetails': 'roadside-park'},
        'speedProfile': {'speedReports': [0, 31, 15, 16]},
        'theRTCM': {'rtcmHeader': {'status': bits(8, 1),
                                   'offsetSet': {'antOffsetX': -2048, 'antOffsetY': 255,
                                                 'antOffsetZ': -512}},
                    'msgs': [octets(24, 53)]},
        'regional': [unknown_ext(ADD_GRP_C, 4, 54)]}}


def bsm_vectors():
    yield ('bsm_minimal', ['msg:BasicSafetyMessage', 'variant:minimal', 'octetstring:fixed',
                           'bitstring:fixed', 'enumerated', 'sequence:optional-absent'],
           bsm_frame(bsm_core()))

    core_min = bsm_core(msgCnt=0, id='00000000', secMark=0, lat=-900000000, long=-1799999999,
                        elev=-4096, accuracy=accuracy(0, 0, 0), transmission='neutral',
                        speed=0, heading=0, angle=-126,
                        accelSet={'long': -2000, 'lat': -2000, 'vert': -127, 'yaw': -32767},
                        brakes={'wheelBrakes': bits(5), 'traction': 'unavailable',
                                'abs': 'unavailable', 'scs': 'unavailable',
                                'brakeBoost': 'unavailable', 'auxBrakes': 'unavailable'},
                        size={'width': 0, 'length': 0})
    yield ('bsm_core_min', ['msg:BasicSafetyMessage', 'int:min', 'int:negative'],
           bsm_frame(core_min))

    core_max = bsm_core(msgCnt=127, id='ffffffff', secMark=65535, lat=900000001,
                        long=1800000001, elev=61439, accuracy=accuracy(255, 255, 65535),
                        transmission='unavailable', speed=8191, heading=28800, angle=127,
                        accelSet={'long': 2001, 'lat': 2001, 'vert': 127, 'yaw': 32767},
                        brakes={'wheelBrakes': bits(5, 0, 1, 2, 3, 4), 'traction': 'engaged',
                                'abs': 'engaged', 'scs': 'engaged', 'brakeBoost': 'on',
                                'auxBrakes': 'reserved'},
                        size={'width': 1023, 'length': 4095})
    yield ('bsm_core_max', ['msg:BasicSafetyMessage', 'int:max'], bsm_frame(core_max))

    yield ('bsm_rich', [
        'msg:BasicSafetyMessage', 'variant:rich', 'partII:vehicleSafetyExt',
        'partII:specialVehicleExt', 'partII:supplementalVehicleExt', 'bitstring:extensible-size',
        'boolean', 'opentype:regional-unknown',
        'sequence:optional-present', 'enumerated:extensible', 'octetstring:variable'],
        bsm_frame(bsm_core(), [vehicle_safety_ext(), special_vehicle_ext(),
                               supplemental_vehicle_ext()],
                  [unknown_ext(ADD_GRP_A, 5, 55)]))

    yield ('bsm_vehicle_safety_path_history_23', [
        'msg:BasicSafetyMessage', 'partII:vehicleSafetyExt', 'seqof:upper-bound',
        'bitstring:extensible-size'],
        bsm_frame(bsm_core(), [vehicle_safety_ext(crumbs=23)]))

    yield ('bsm_vehicle_safety_events_only', [
        'msg:BasicSafetyMessage', 'partII:vehicleSafetyExt', 'bitstring:extensible-size',
        'seqof:size-1'], bsm_frame(bsm_core(), [vehicle_safety_ext(rich=False)]))

    yield ('bsm_bit_strings_outside_root', [
        'msg:BasicSafetyMessage', 'bitstring:extensible-size-outside-root', X697_BITSTRING_TAG,
        'partII:vehicleSafetyExt'],
        bsm_frame(bsm_core(), [{'partII-Id': 0, 'partII-Value': {
            'events': {'value': 'ffff', 'length': 16},
            'lights': {'value': 'a040', 'length': 10}}}]))

    yield ('bsm_part2_eight', [
        'msg:BasicSafetyMessage', 'seqof:upper-bound', 'partII:vehicleSafetyExt',
        'partII:specialVehicleExt', 'partII:supplementalVehicleExt'],
        bsm_frame(bsm_core(), [
            vehicle_safety_ext(rich=False),
            {'partII-Id': 1, 'partII-Value': {}},
            {'partII-Id': 2, 'partII-Value': {}},
            {'partII-Id': 2, 'partII-Value': {'classification': 1}},
            {'partII-Id': 1, 'partII-Value': {'description': {'typeEvent': 7186}}},
            {'partII-Id': 0, 'partII-Value': {'events': bits(13), 'lights': bits(9)}},
            {'partII-Id': 2, 'partII-Value': {'speedProfile': {'speedReports': [5]}}},
            vehicle_safety_ext(rich=False)]))


# ============================================================================ SPaT (19)

def movement(group, events, **optional):
    m = {'signalGroup': group, 'state-time-speed': events}
    m.update(optional)
    return m


def intersection_state(iid, states, revision=1, status=bits(16), **optional):
    s = {'id': {'id': iid}, 'revision': revision, 'status': status, 'states': states}
    s.update(optional)
    return s


def spat_vectors():
    yield ('spat_minimal', ['msg:SPAT', 'variant:minimal', 'seqof:size-1',
                            'sequence:optional-absent', 'bitstring:fixed', 'enumerated'],
           frame(SPAT, {'intersections': [intersection_state(
               101, [movement(2, [{'eventState': 'stop-And-Remain'}])])]}))

    yield ('spat_rich', [
        'msg:SPAT', 'variant:rich', 'sequence:optional-present', 'ia5string', 'boolean',
        'enumerated:extensible', 'int:max', 'opentype:regional-unknown'], spat_rich())

    yield ('spat_all_phase_states', ['msg:SPAT', 'enumerated'], frame(SPAT, {
        'intersections': [intersection_state(102, [movement(5, [
            {'eventState': state, 'timing': {'minEndTime': 100 * i}}
            for i, state in enumerate(PHASE_STATES)])])]}))

    yield ('spat_regional_extensions', [
        'msg:SPAT', 'addgrpc:IntersectionState', 'addgrpc:ConnectionManeuverAssist',
        'addgrpb:MovementEvent', 'opentype:regional-known', 'node:node-XY3',
        'seqof:upper-bound'], spat_regional())


PHASE_STATES = ['unavailable', 'dark', 'stop-Then-Proceed', 'stop-And-Remain', 'pre-Movement',
                'permissive-Movement-Allowed', 'protected-Movement-Allowed',
                'permissive-clearance', 'protected-clearance', 'caution-Conflicting-Traffic']


def spat_rich():
    timing = {'startTime': 0, 'minEndTime': 36111, 'maxEndTime': 36000, 'likelyTime': 35990,
              'confidence': 15, 'nextTime': 1200}
    speeds = [{'type': 'greenwave', 'speed': 500, 'confidence': 'prec1ms', 'distance': 10000,
               'class': 3, 'regional': [unknown_ext(ADD_GRP_A, 1, 61)]},
              {'type': 'none'}]
    assist = {'connectionID': 11, 'queueLength': 45, 'availableStorageLength': 120,
              'waitOnStop': True, 'pedBicycleDetect': False,
              'regional': [unknown_ext(ADD_GRP_B, 2, 62)]}
    states = [
        movement(2, [{'eventState': 'protected-Movement-Allowed', 'timing': timing,
                      'speeds': speeds, 'regional': [unknown_ext(ADD_GRP_A, 1, 63)]},
                     {'eventState': 'protected-clearance', 'timing': {'minEndTime': 36111}}],
                 movementName='EB through', maneuverAssistList=[assist],
                 regional=[unknown_ext(ADD_GRP_A, 2, 64)]),
        movement(4, [{'eventState': 'stop-And-Remain'}]),
    ]
    ist = intersection_state(
        4020, states, revision=127, status=bits(16, 0, 4, 10), name='Main St & Work Zone Ave',
        moy=527040, timeStamp=59999, enabledLanes=[1, 5, 20],
        maneuverAssistList=[{'connectionID': 255}],
        regional=[unknown_ext(ADD_GRP_B, 1, 65)])
    ist['id']['region'] = 65535
    return frame(SPAT, {'timeStamp': 241200, 'name': 'County signal system',
                        'intersections': [ist], 'regional': [unknown_ext(ADD_GRP_A, 3, 66)]})


def spat_regional():
    me_b = {'startTime': 0, 'minEndTime': 2402, 'maxEndTime': 2402, 'likelyTime': 9001,
            'confidence': 7, 'nextTime': 9001}
    cma_c = {'vehicleToLanePositions': [{'stationID': 4294967295, 'laneID': 1},
                                        {'stationID': 0, 'laneID': 255},
                                        {'stationID': 12345, 'laneID': 2},
                                        {'stationID': 67890, 'laneID': 3},
                                        {'stationID': 1, 'laneID': 4}],
             'rsuDistanceFromAnchor': {'node-XY3': {'x': -2048, 'y': 2047}}}
    ist_c = {'activePrioritizations': [{'stationID': 99, 'priorState': 'granted',
                                        'signalGroup': 2}]}
    states = [movement(2, [{'eventState': 'permissive-Movement-Allowed',
                            'regional': [ext(ADD_GRP_B, me_b)]},
                           {'eventState': 'stop-And-Remain',
                            'regional': [ext(ADD_GRP_B, {'minEndTime': 0})]}],
                       maneuverAssistList=[{'connectionID': 1,
                                            'regional': [ext(ADD_GRP_C, cma_c)]}])]
    return frame(SPAT, {'intersections': [intersection_state(
        103, states, regional=[ext(ADD_GRP_C, ist_c), ext(ADD_GRP_C, {})])]})


# ============================================================================ other messages

def csr_vectors():
    yield ('csr_minimal', ['msg:CommonSafetyRequest', 'variant:minimal', 'seqof:size-1',
                           'enumerated:extensible'],
           frame(CSR, {'requests': ['reserved']}))
    yield ('csr_rich', ['msg:CommonSafetyRequest', 'variant:rich', 'seqof:upper-bound',
                        'octetstring:fixed', 'opentype:regional-unknown', 'int:max'],
           frame(CSR, {'timeStamp': 527040, 'msgCnt': 127, 'id': '0badf00d',
                       'requests': [REQUESTED_ITEMS[i % len(REQUESTED_ITEMS)]
                                    for i in range(32)],
                       'regional': [unknown_ext(ADD_GRP_A, 4, 71)]}))


REQUESTED_ITEMS = ['reserved', 'itemA', 'itemB', 'itemC', 'itemD', 'itemE', 'itemF', 'itemG',
                   'itemI', 'itemJ', 'itemK', 'itemL', 'itemM', 'itemN', 'itemO', 'itemP',
                   'itemQ']


def rsa_value(rich):
    value = {'msgCnt': 3, 'typeEvent': WORK_ZONE}
    if rich:
        value.update({'timeStamp': 241200, 'description': [LANE_CLOSED, LEFT_LANE, WORKERS,
                                                          speed_itis(25), MPH, 0, 65535, 1],
                      'priority': 'ff', 'heading': heading_slice(10, 11, 12),
                      'extent': 'useFor1000meters',
                      'position': full_position(SITE_LAT, SITE_LON, rich=True),
                      'furtherInfoID': '1234', 'regional': [unknown_ext(ADD_GRP_A, 2, 72)]})
    return value


def rsa_vectors():
    yield ('rsa_minimal', ['msg:RoadSideAlert', 'variant:minimal', 'itis:1025'],
           frame(RSA, rsa_value(False)))
    yield ('rsa_rich', ['msg:RoadSideAlert', 'variant:rich', 'seqof:upper-bound',
                        'octetstring:fixed', 'itis:769', 'itis:8195', 'itis:8720', 'enumerated'],
           frame(RSA, rsa_value(True)))


def eva_vectors():
    yield ('eva_minimal', ['msg:EmergencyVehicleAlert', 'variant:minimal'],
           frame(EVA, {'rsaMsg': {'msgCnt': 0, 'typeEvent': 8961}}))
    yield ('eva_rich', ['msg:EmergencyVehicleAlert', 'variant:rich', 'enumerated:extensible',
                        'octetstring:fixed', 'opentype:regional-unknown'], frame(EVA, {
        'timeStamp': 241200, 'id': '00c0ffee', 'rsaMsg': rsa_value(True),
        'responseType': 'stopAndGoMovement',
        'details': {'notUsed': 31, 'sirenUse': 'inUse', 'lightsUse': 'inUse',
                    'multi': 'multiVehicle',
                    'events': {'notUsed': 0, 'event': bits(16, 1, 2, 3)},
                    'responseType': 'emergency'},
        'mass': 255, 'basicType': 'special', 'vehicleType': 'military-vehicles',
        'responseEquip': 'ambulance', 'responderType': 'ambulance-units',
        'regional': [unknown_ext(ADD_GRP_B, 3, 73)]}))


def ica_vectors():
    yield ('ica_minimal', ['msg:IntersectionCollision', 'variant:minimal',
                           'bitstring:extensible-size', 'choice'],
           frame(ICA, {'msgCnt': 1, 'id': '01020304', 'intersectionID': {'id': 4020},
                       'laneNumber': {'approach': 15}, 'eventFlag': bits(13)}))
    yield ('ica_rich', ['msg:IntersectionCollision', 'variant:rich', 'bitstring:extensible-size',
                        'choice', 'opentype:regional-unknown'],
           frame(ICA, {'msgCnt': 2, 'id': '01020304', 'timeStamp': 1,
                       'partOne': bsm_core(),
                       'path': path_history(3, rich=True),
                       'pathPrediction': {'radiusOfCurve': 32767, 'confidence': 0},
                       'intersectionID': {'region': 0, 'id': 65535},
                       'laneNumber': {'lane': 255},
                       'eventFlag': bits(13, *range(13)),
                       'regional': [unknown_ext(ADD_GRP_C, 1, 74)]}))


def nmea_sentence(body):
    checksum = 0
    for ch in body:
        checksum ^= ord(ch)
    return '$%s*%02X\r\n' % (body, checksum)


def nmea_vectors():
    gga = nmea_sentence('GNGGA,143241.25,4207.4074,N,08345.9259,W,4,14,0.7,271.0,M,-34.2,M,'
                        '1.0,0042')
    yield ('nmea_minimal', ['msg:NMEAcorrections', 'variant:minimal', 'octetstring:variable'],
           frame(NMEA, {'payload': ascii_hex(gga)}))
    rich_payload = ''.join(nmea_sentence(s) for s in [
        'GNRMC,143241.25,A,4207.4074,N,08345.9259,W,12.4,270.0,170625,,,R',
        'GNGST,143241.25,0.9,0.02,0.01,80.0,0.02,0.01,0.03',
        'GNVTG,270.0,T,,M,12.4,N,23.0,K,R'])
    assert len(rich_payload) >= 128
    yield ('nmea_rich', ['msg:NMEAcorrections', 'variant:rich', 'octetstring:variable',
                         'enumerated:extensible'],
           frame(NMEA, {'timeStamp': 241201, 'rev': 'rev4', 'msg': 32767, 'wdCount': 1023,
                        'payload': ascii_hex(rich_payload),
                        'regional': [unknown_ext(ADD_GRP_A, 1, 75)]}))
    yield ('nmea_payload_max', ['msg:NMEAcorrections', 'octetstring:variable',
                                'octetstring:near-max'],
           frame(NMEA, {'payload': octets(1023, 76)}))


def pdm_vectors():
    yield ('pdm_minimal', ['msg:ProbeDataManagement', 'variant:minimal', 'choice'],
           frame(PDM, {'sample': {'sampleStart': 0, 'sampleEnd': 255},
                       'directions': heading_slice(), 'term': {'termtime': 1},
                       'snapshot': {'snapshotTime': {'speed1': 0, 'time1': 0, 'speed2': 31,
                                                     'time2': 61}},
                       'txInterval': 0}))
    yield ('pdm_rich', ['msg:ProbeDataManagement', 'variant:rich', 'choice', 'boolean',
                        'enumerated:extensible', 'int:negative', 'seqof:upper-bound'],
           frame(PDM, {'timeStamp': 100, 'sample': {'sampleStart': 10, 'sampleEnd': 20},
                       'directions': heading_slice(*range(0, 16, 2)),
                       'term': {'termDistance': 30000},
                       'snapshot': {'snapshotDistance': {'distance1': 1023, 'speed1': 31,
                                                         'distance2': 0, 'speed2': 0}},
                       'txInterval': 61,
                       'dataElements': [
                           {'dataType': PDM_TYPES[i % len(PDM_TYPES)]} if i % 3 else
                           {'dataType': PDM_TYPES[i % len(PDM_TYPES)], 'subType': 1 + i % 15,
                            'sendOnLessThenValue': -32767, 'sendOnMoreThenValue': 32767,
                            'sendAll': bool(i % 2)}
                           for i in range(32)],
                       'regional': [unknown_ext(ADD_GRP_A, 1, 77)]}))


PDM_TYPES = ['unknown', 'lights', 'wipers', 'brakes', 'stab', 'trac', 'abs', 'sunS', 'rainS',
             'airTemp', 'steering', 'vertAccelThres', 'vertAccel', 'hozAccelLong',
             'hozAccelLat', 'hozAccelCon', 'accel4way', 'confidenceSet', 'obDist', 'obDirect',
             'yaw', 'yawRateCon', 'dateTime', 'fullPos', 'position2D', 'position3D', 'vehicle',
             'speedHeadC', 'speedC']


def pvd_vectors():
    yield ('pvd_minimal', ['msg:ProbeVehicleData', 'variant:minimal', 'seqof:size-1'],
           frame(PVD, {'startVector': full_position(SITE_LAT, SITE_LON), 'vehicleType': {},
                       'snapshots': [{'thePosition': full_position(SITE_LAT + 10, SITE_LON)}]}))
    status = {
        'lights': bits(9, 0, 1), 'lightBar': 'yellowCautionLights',
        'wipers': {'statusFront': 'low', 'rateFront': 30},
        'brakeStatus': {'wheelBrakes': bits(5, 1, 3), 'traction': 'on', 'abs': 'engaged',
                        'scs': 'off', 'brakeBoost': 'on', 'auxBrakes': 'off'},
        'brakePressure': 'maxPressure', 'roadFriction': 50, 'sunData': 1000,
        'rainData': 'heavyDownpour', 'airTemp': 0, 'airPres': 255,
        'steering': {'angle': -126, 'confidence': 'prec0-02deg', 'rate': -127,
                     'wheels': -128},
        'accelSets': {'accel4way': {'long': 0, 'lat': 0, 'vert': 0, 'yaw': 0},
                      'vertAccelThres': bits(5, 0), 'yawRateCon': 'degSec-000-01',
                      'hozAccelCon': 'accl-000-01',
                      'confidenceSet': {
                          'accelConfidence': {'yawRate': 'unavailable',
                                              'acceleration': 'accl-100-00',
                                              'steeringWheelAngle': 'prec2deg'},
                          'speedConfidence': {'heading': 'prec0-0125deg',
                                              'speed': 'prec0-01ms',
                                              'throttle': 'prec0-5percent'},
                          'timeConfidence': 'time-000-000-000-000-01',
                          'posConfidence': {'pos': 'a1cm', 'elevation': 'elev-000-01'},
                          'steerConfidence': 'prec1deg', 'headingConfidence': 'prec10deg',
                          'throttleConfidence': 'unavailable'}},
        'object': {'obDist': 150, 'obDirect': 900,
                   'dateTime': {'year': 2025}},
        'fullPos': full_position(SITE_LAT, SITE_LON, rich=True),
        'throttlePos': 200,
        'speedHeadC': {'heading': 'prec05deg', 'speed': 'prec5ms', 'throttle': 'prec10percent'},
        'speedC': 'prec0-1ms',
        'vehicleData': {'height': 127, 'bumpers': {'front': 1, 'rear': 2}, 'mass': 3,
                        'trailerWeight': 0, 'type': 'axleCnt7MultiTrailer'},
        'vehicleIdent': {'name': 'Probe 7'},
        'j1939data': {
            'tires': [{'location': 0, 'pressure': 250, 'temp': -8736,
                       'wheelSensorStatus': 'notSupported', 'wheelEndElectFault': 'isError',
                       'leakageRate': 64255, 'detection': 'underPressure'}, {}],
            'axles': [{'location': 1, 'weight': 64255}, {}],
            'trailerWeight': 100, 'cargoWeight': 64255, 'steeringAxleTemperature': -40,
            'driveAxleLocation': 255, 'driveAxleLiftAirPressure': 1000,
            'driveAxleTemperature': 210, 'driveAxleLubePressure': 250,
            'steeringAxleLubePressure': 0},
        'weatherReport': {'isRaining': 'error', 'rainRate': 1,
                          'precipSituation': 'frozenPrecipitationHeavy',
                          'solarRadiation': 65535, 'friction': 0},
        'gnssStatus': bits(8, 7)}
    yield ('pvd_rich', ['msg:ProbeVehicleData', 'variant:rich', 'choice',
                        'bitstring:extensible-size', 'octetstring:variable', 'ia5string',
                        'int:min', 'int:max', 'opentype:regional-unknown'], frame(PVD, {
        'timeStamp': 527040, 'segNum': 32767,
        'probeID': {'name': 'Fleet probe 12', 'vin': ascii_hex('1FTFW1E50PFA00001'),
                    'ownerCode': 'DOT-ROADWORK', 'id': {'stationID': 4294967295},
                    'vehicleType': 'car', 'vehicleClass': {'rEquip': 'dump-truck'}},
        'startVector': full_position(SITE_LAT, SITE_LON, rich=True),
        'vehicleType': {'keyType': 0, 'role': 'military', 'iso3883': 0, 'hpmsType': 'none',
                        'vehicleType': 'all-vehicles', 'responseEquip': 'ground-fire-suppression',
                        'responderType': 'emergency-vehicle-units', 'fuelType': 0,
                        'regional': [unknown_ext(ADD_GRP_A, 1, 78)]},
        'snapshots': [
            {'thePosition': full_position(SITE_LAT + 10, SITE_LON - 10),
             'safetyExt': vehicle_safety_ext(crumbs=2)['partII-Value'], 'dataSet': status},
            {'thePosition': full_position(SITE_LAT + 20, SITE_LON - 20),
             'dataSet': {'vehicleIdent': {'id': {'entityID': 'cafe0001'},
                                          'vehicleClass': {'vGroup': 'trucks'}}}},
            {'thePosition': full_position(SITE_LAT + 30, SITE_LON - 30),
             'dataSet': {'vehicleIdent': {'vehicleClass': {'rGroup': 'fire-units'}}}}],
        'regional': [unknown_ext(ADD_GRP_C, 2, 79)]}))


def rtcm_vectors():
    yield ('rtcm_minimal', ['msg:RTCMcorrections', 'variant:minimal', 'octetstring:variable',
                            'seqof:size-1', 'enumerated:extensible'],
           frame(RTCM, {'msgCnt': 0, 'rev': 'rtcmRev3', 'msgs': [octets(1, 80)]}))
    lengths = [1, 127, 128, 255, 1000]
    yield ('rtcm_rich', ['msg:RTCMcorrections', 'variant:rich', 'octetstring:variable',
                         'seqof:upper-bound', 'bitstring:fixed', 'int:negative'], frame(RTCM, {
        'msgCnt': 99, 'rev': 'rtcmRev2', 'timeStamp': 241202,
        'anchorPoint': full_position(SITE_LAT, SITE_LON, rich=True),
        'rtcmHeader': {'status': bits(8, 1, 2, 7),
                       'offsetSet': {'antOffsetX': 2047, 'antOffsetY': -256, 'antOffsetZ': 511}},
        'msgs': [octets(n, 81 + i) for i, n in enumerate(lengths)],
        'regional': [unknown_ext(ADD_GRP_A, 1, 86)]}))
    yield ('rtcm_message_max', ['msg:RTCMcorrections', 'octetstring:variable',
                                'octetstring:near-max'],
           frame(RTCM, {'msgCnt': 1, 'rev': 'unknown', 'msgs': [octets(1023, 87),
                                                                 octets(1022, 88)]}))


def srm_vectors():
    yield ('srm_minimal', ['msg:SignalRequestMessage', 'variant:minimal', 'choice'],
           frame(SRM, {'second': 0, 'requestor': {'id': {'entityID': '00000001'}}}))
    request = {'request': {'id': {'region': 26, 'id': 4020}, 'requestID': 255,
                           'requestType': 'priorityRequest',
                           'inBoundLane': {'lane': 1}, 'outBoundLane': {'connection': 11},
                           'regional': [unknown_ext(ADD_GRP_A, 1, 89)]},
               'minute': 527040, 'second': 65535, 'duration': 2000,
               'regional': [unknown_ext(ADD_GRP_A, 1, 90)]}
    yield ('srm_rich', ['msg:SignalRequestMessage', 'variant:rich', 'choice', 'ia5string',
                        'int:max', 'int:negative', 'bitstring:fixed', 'enumerated:extensible',
                        'opentype:regional-unknown', 'addgrpc:Position3D'], frame(SRM, {
        'timeStamp': 241203, 'second': 59000, 'sequenceNumber': 5,
        'requests': [request, {'request': {'id': {'id': 4021}, 'requestID': 0,
                                           'requestType': 'priorityCancellation',
                                           'inBoundLane': {'approach': 3}}}],
        'requestor': {
            'id': {'stationID': 4294967295},
            'type': {'role': 'roadWork', 'subrole': 'requestSubRole3',
                     'request': 'requestImportanceLevel14', 'iso3883': 7,
                     'hpmsType': 'axleCnt3', 'regional': unknown_ext(ADD_GRP_A, 2, 91)},
            'position': {'position': pos3d(SITE_LAT, SITE_LON, SITE_ELEV,
                                           [ext(ADD_GRP_C, {'altitude': {
                                               'value': 800001, 'confidence': 'outOfRange'}})]),
                         'heading': 27000, 'speed': {'transmisson': 'reverseGears',
                                                     'speed': 100}},
            'name': 'Plow 12', 'routeName': 'Route 9 maintenance',
            'transitStatus': bits(8, 0, 5), 'transitOccupancy': 'occupancyFull',
            'transitSchedule': -122, 'regional': [unknown_ext(ADD_GRP_B, 1, 92)]},
        'regional': [unknown_ext(ADD_GRP_A, 1, 93)]}))


def ssm_vectors():
    yield ('ssm_minimal', ['msg:SignalStatusMessage', 'variant:minimal', 'choice'],
           frame(SSM, {'second': 1, 'status': [{'sequenceNumber': 0, 'id': {'id': 1},
                                                'sigStatus': [{'inboundOn': {'approach': 0},
                                                               'status': 'unknown'}]}]}))
    package = {'requester': {'id': {'entityID': '0a0b0c0d'}, 'request': 17,
                             'sequenceNumber': 5, 'role': 'transit',
                             'typeData': {'role': 'transit', 'subrole': 'requestSubRole1',
                                          'request': 'requestImportanceLevelUnKnown',
                                          'regional': unknown_ext(ADD_GRP_A, 1, 94)}},
               'inboundOn': {'lane': 1}, 'outboundOn': {'connection': 11}, 'minute': 241203,
               'second': 1000, 'duration': 65535, 'status': 'granted',
               'regional': [unknown_ext(ADD_GRP_A, 1, 95)]}
    yield ('ssm_rich', ['msg:SignalStatusMessage', 'variant:rich', 'choice', 'enumerated',
                        'opentype:regional-unknown', 'seqof:upper-bound'], frame(SSM, {
        'timeStamp': 241203, 'second': 1000, 'sequenceNumber': 6,
        'status': [{'sequenceNumber': 6, 'id': {'region': 26, 'id': 4020},
                    'sigStatus': [package] + [{'inboundOn': {'approach': i % 16},
                                               'status': SSM_STATUSES[i % 8]}
                                              for i in range(31)],
                    'regional': [unknown_ext(ADD_GRP_B, 1, 96)]}],
        'regional': [unknown_ext(ADD_GRP_C, 1, 97)]}))


SSM_STATUSES = ['unknown', 'requested', 'processing', 'watchOtherTraffic', 'granted',
                'rejected', 'maxPresence', 'reserviceLocked']


def psm_base(**overrides):
    value = {'basicType': 'aPEDESTRIAN', 'secMark': 30000, 'msgCnt': 9, 'id': '5e5e5e5e',
             'position': pos3d(SITE_LAT + 200, SITE_LON - 150), 'accuracy': accuracy(),
             'speed': 70, 'heading': 9000}
    value.update(overrides)
    return value


def psm_vectors():
    yield ('psm_minimal', ['msg:PersonalSafetyMessage', 'variant:minimal',
                           'enumerated:extensible', 'octetstring:fixed'],
           frame(PSM, psm_base()))
    yield ('psm_rich_road_worker', [
        'msg:PersonalSafetyMessage', 'variant:rich', 'bitstring:extensible-size', 'boolean',
        'choice', 'choice:extensible', 'enumerated:extensible', 'opentype:regional-unknown'],
        frame(PSM, psm_base(
            basicType='aPUBLICSAFETYWORKER', position=pos3d(SITE_LAT, SITE_LON, SITE_ELEV),
            accelSet={'long': 10, 'lat': -10, 'vert': 1, 'yaw': 0},
            pathHistory=path_history(2), pathPrediction={'radiusOfCurve': 0,
                                                          'confidence': 100},
            propulsion={'human': 'onFoot'}, useState=bits(9, 2, 8), crossRequest=False,
            crossState=True, clusterSize='medium', clusterRadius=100,
            eventResponderType='aDOTWorker', activityType=bits(6, 1, 2),
            activitySubType=bits(7, 2), assistType=bits(6, 0), sizing=bits(5, 2, 4),
            attachment='cart', attachmentRadius=200, animalType='unavailable',
            regional=[unknown_ext(ADD_GRP_A, 2, 98)])))
    yield ('psm_cyclist_motor', ['msg:PersonalSafetyMessage', 'choice', 'choice:extensible',
                                 'bitstring:extensible-size'],
           frame(PSM, psm_base(basicType='aPEDALCYCLIST', propulsion={'motor': 'bicycle'},
                               useState=bits(9), sizing=bits(5))))
    yield ('psm_animal', ['msg:PersonalSafetyMessage', 'choice', 'enumerated:extensible'],
           frame(PSM, psm_base(basicType='anANIMAL',
                               propulsion={'animal': 'animalDrawnCarriage'},
                               animalType='farm')))


def test_message_vectors():
    """TestMessage00..15: header and a single regional extension, in turns."""
    for i in range(16):
        value = {}
        if i % 4 in (1, 3):
            value['header'] = {'year': 2025, 'timeStamp': 1000 * i, 'secMark': 65535 - i,
                               'msgIssueRevision': i} if i % 8 == 1 else {'secMark': i}
        if i % 4 in (2, 3):
            value['regional'] = unknown_ext(i % 5, i + 1, 100 + i)
        covers = ['msg:TestMessage%02d' % i]
        covers.append('sequence:optional-present' if value else 'sequence:optional-absent')
        if 'regional' in value:
            covers.append('opentype:regional-unknown')
        yield ('test_message_%02d' % i, covers, frame(TEST_MESSAGE_00 + i, value))


# ============================================================================ engine

FAMILIES = [map_vectors, tim_vectors, bsm_vectors, spat_vectors, csr_vectors, eva_vectors,
            ica_vectors, nmea_vectors, pdm_vectors, pvd_vectors, rsa_vectors, rtcm_vectors,
            srm_vectors, ssm_vectors, psm_vectors, test_message_vectors]


def load_oracle():
    sys.path.insert(0, os.path.join(SHARED, 'j2735'))
    import j2735_2020  # noqa: E402  (pycrate-compiled J2735 2020)
    return j2735_2020.MessageFrame.MessageFrame


def to_uper(mf, jer):
    mf.from_jer(json.dumps(jer))
    return mf.to_uper()


def to_jer(mf, uper):
    mf.from_uper(uper)
    return json.loads(mf.to_jer())


def scalars_and_keys(value, acc):
    """Every key, string value and integer value (as text) found in a JER value."""
    if isinstance(value, dict):
        for k, v in value.items():
            acc.add(k)
            scalars_and_keys(v, acc)
    elif isinstance(value, list):
        for v in value:
            scalars_and_keys(v, acc)
    elif isinstance(value, (str, int)) and not isinstance(value, bool):
        acc.add(str(value))
    return acc


MESSAGE_NAMES = {MAP: 'MapData', SPAT: 'SPAT', BSM: 'BasicSafetyMessage',
                 CSR: 'CommonSafetyRequest', EVA: 'EmergencyVehicleAlert',
                 ICA: 'IntersectionCollision', NMEA: 'NMEAcorrections',
                 PDM: 'ProbeDataManagement', PVD: 'ProbeVehicleData', RSA: 'RoadSideAlert',
                 RTCM: 'RTCMcorrections', SRM: 'SignalRequestMessage',
                 SSM: 'SignalStatusMessage', TIM: 'TravelerInformation',
                 PSM: 'PersonalSafetyMessage'}
MESSAGE_NAMES.update({TEST_MESSAGE_00 + i: 'TestMessage%02d' % i for i in range(16)})
PART2_NAMES = {0: 'vehicleSafetyExt', 1: 'specialVehicleExt', 2: 'supplementalVehicleExt'}
DERIVED_PREFIXES = ('msg:', 'partII:', 'opentype:')


def derived_tags(jer, uper):
    """Tags read off the value and its encoding rather than declared by hand."""
    tags = {'msg:' + MESSAGE_NAMES[jer['messageId']]}
    first = uper[2]                     # MessageFrame.value length determinant
    if first & 0xC0 == 0xC0:
        tags.add('opentype:fragmented')
    elif first & 0x80:
        tags.add('opentype:length-2byte')

    def walk(value):
        if isinstance(value, dict):
            if 'regExtValue' in value:
                known = isinstance(value['regExtValue'], dict)
                tags.add('opentype:regional-' + ('known' if known else 'unknown'))
                if not known and len(value['regExtValue']) >= 256:
                    tags.add('opentype:regext-length-2byte')
            if 'partII-Id' in value:
                tags.add('partII:' + PART2_NAMES[value['partII-Id']])
            for v in value.values():
                walk(v)
        elif isinstance(value, list):
            for v in value:
                walk(v)
    walk(jer)
    return tags


def check_covers(name, declared, jer, derived):
    """Declared tags that can be checked against the JER or the bytes must hold."""
    found = scalars_and_keys(jer, set())
    for tag in declared:
        if tag.startswith(DERIVED_PREFIXES):
            if tag not in derived:
                raise SystemExit('%s: tag %s does not hold for the value' % (name, tag))
        elif tag.startswith(CHECKED_TAG_PREFIXES):
            key = tag.split(':', 1)[1]
            if key == 'speed-number':
                ok = any(str(12544 + n) in found for n in range(0, 200))
            else:
                ok = key in found
            if not ok:
                raise SystemExit('%s: tag %s not found in its JER' % (name, tag))


def bare_bit_strings(value):
    """pycrate's JER of an extensible-size BIT STRING: {"value": h, "length": n} -> h."""
    if isinstance(value, dict):
        if set(value) == {'value', 'length'}:
            return value['value']
        return {k: bare_bit_strings(v) for k, v in value.items()}
    if isinstance(value, list):
        return [bare_bit_strings(v) for v in value]
    return value


def make_vector(mf, name, covers, jer):
    try:
        uper = to_uper(mf, jer)
    except Exception as e:
        raise SystemExit('%s: pycrate refused the value: %s: %s' % (name, type(e).__name__, e))
    back = to_jer(mf, uper)
    if X697_BITSTRING_TAG in covers:
        # pycrate prints these bare and could not read its own output back: keep the X.697
        # form we gave it, and prove the decoded value (with its length) re-encodes exactly.
        if back != bare_bit_strings(jer) or mf.to_uper() != uper:
            raise SystemExit('%s: X.697 BIT STRING form does not round-trip' % name)
        back = jer
    elif back != jer:
        raise SystemExit('%s: JER does not round-trip through pycrate:\n  in:  %s\n  out: %s'
                         % (name, json.dumps(jer, sort_keys=True),
                            json.dumps(back, sort_keys=True)))
    elif to_uper(mf, back) != uper:
        raise SystemExit('%s: re-encoding the decoded JER gives other bytes' % name)
    derived = derived_tags(back, uper)
    check_covers(name, covers, back, derived)
    return {'name': name, 'covers': sorted(set(covers) | derived), 'uper': uper.hex(),
            'jer': back}


def make_all():
    mf = load_oracle()
    vectors = {}
    for family in FAMILIES:
        for name, covers, jer in family():
            if name in vectors:
                raise SystemExit('duplicate vector name ' + name)
            vectors[name] = make_vector(mf, name, covers, jer)
    covered = set(t for v in vectors.values() for t in v['covers'])
    missing = [t for t in REQUIRED_TAGS if t not in covered]
    if missing:
        raise SystemExit('required tags not covered: ' + ', '.join(missing))
    lines = [json.dumps(vectors[n], sort_keys=True, separators=(',', ':'))
             for n in sorted(vectors)]
    return '\n'.join(lines) + '\n', vectors


def main():
    return vector_file.run(__doc__.split('\n\n')[0], OUT, REPO, make_all)


if __name__ == '__main__':
    sys.exit(main())
