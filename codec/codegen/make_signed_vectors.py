#!/usr/bin/env python3
"""Make independent IEEE 1609.2 signed-data test vectors (issue 13, part 5).

What it makes
    codec/tests/vectors/ieee1609dot2_signed.jsonl: one JSON object a line, sorted by name:
        {"name", "case", "expect": "valid" | the failure reason in words,
         "coer": hex of the whole Ieee1609Dot2Data, "signer": "digest" | "certificate" |
         "certificate-chain" | "self", "psid", "generation_time", "expiry_time",
         "generation_location", "frame": the J2735 MessageFrame (UPER hex) inside,
         "trust_anchors": {"root", "ca"} certificate COER hex, "known_certs": certificates a
         verifier has already seen (for the digest signer), "now": the verifier's clock
         (Time64), the verifier's profile ("future_tolerance_us", "past_window_us",
         "max_lifetime_us"), "self_public_key" (self signer only, compressed SEC1 hex),
         "rsig_form": "x-only" | "compressed-y", "pair" (repeat), "differs_from" (the valid
         vector an invalid one was made from), "note", "untrusted_root" (its root),
         "certificate_type": "implicit" and "reconstructed_public_key" (ECQV vectors),
         "wsmp": [{"bytes", "expect"}] WAVE Short Messages around it (base vector only)}.

Independence
    Nothing here is computed by the project's code. ASN.1 structure and COER bytes come from
    pycrate 0.8.1's IEEE 1609.2 module (pycrate_asn1dir.ITS_IEEE1609_2: modules Ieee1609Dot2
    and Ieee1609Dot2BaseTypes, the 1609.2-2016 ASN.1 as shipped with ETSI TS 103 097), via
    to_coer()/from_coer(). NIST P-256 ECDSA and SHA-256 come from Python's `cryptography`
    package; signatures are deterministic (RFC 6979) through
    ec.ECDSA(hashes.SHA256(), deterministic_signing=True) (cryptography >= 42). The y parity
    of the signature point R (for rSig in compressed-y form) is recovered with a few lines of
    textbook affine P-256 arithmetic below (R = s^-1 e G + s^-1 r Q), checked against
    x(R) == r.

Hash to sign (IEEE 1609.2-2016 5.3.1, "Signature algorithms"; the SignedData and
    certificate clauses point to it. Clause numbers from memory of the 2016 text, which was
    not at hand; the rule matches published 1609.2 reference scripts)
    Data input        = COER of ToBeSignedData (for a certificate: of its ToBeSignedCertificate)
    Signer identifier input = COER of the signer's certificate; the empty string when the
        signer is `self` (and for a self-signed root certificate)
    H = SHA-256( SHA-256(Data input) || SHA-256(Signer identifier input) )
    ECDSA (FIPS 186-4) is run with e = H, i.e. ECDSA-with-SHA-256 over the 64-octet
    concatenation SHA-256(Data input) || SHA-256(Signer identifier input); this is what
    `key.sign(concat, ECDSA(SHA256()))` does. The signer certificate is always the end-entity
    certificate (the first of a chain), whatever the SignerIdentifier form is.
    HashedId8(cert) = the low-order (last) 8 octets of SHA-256(cert COER).
    Certificates are written canonically: public keys in compressed-y form, certificate
    signatures with rSig x-only, so the hash of a certificate is the hash of its bytes as sent.

Times (Time32 / Time64 of Ieee1609Dot2BaseTypes)
    Time32 = TAI seconds, Time64 = TAI microseconds, since 2004-01-01 00:00:00 UTC. UTC -> TAI
    here adds LEAP_SECONDS_SINCE_2004 = 5 (the leap seconds inserted at the ends of 2005-12,
    2008-12, 2012-06, 2015-06 and 2016-12); valid for any date after 2017-01-01.

Cases (see CASES below): valid for every signer kind and both rSig forms, TIM and MAP;
    payload bit flipped; signature bit flipped; wrong PSID; message expired (expiryTime past);
    certificate expired; certificate not yet valid; chain to an untrusted root; region miss;
    WSMP (IEEE 1609.3) around the base vector and its bare frame, right and wrong T-header
    PSIDs (member "wsmp": bytes and expectation each);
    generation time in the future; generation time too old (no expiry time, past the past
    window); signed once with an expiry time a day after a generation two hours back (valid,
    TIM and MAP: the deposited-TIM pattern); expiry before generation; lifetime over the
    7-day cap; the misread PSID 32771 (TIM's p-encoded octets read as the integer) in both
    header and certificate; a digest signer whose certificate was not seen; repeat (a pair:
    the same bytes twice, the second expects "valid (repeat)"). PSIDs are the IEEE 1609.2
    integers (TIM 131, MAP 2113687). Truncation at every octet is not written out: a
    verifier-side loop over every "valid" vector (every prefix must be rejected).
    Regions: the RSU certificate's circle (5 km), and the same RSU with a rectangle or a
    kite-shaped polygon instead (a valid vector inside, a region miss outside each).
    Implicit certificates (ECQV, SEC 4 as profiled by 1609.2): an RSU certificate of type
    implicit issued by the CA, valid vectors with it as digest, certificate and chain signer
    (see the ECQV section for the hash e and its one assumption).

Self-check
    Every vector is decoded back by pycrate and re-encoded to the same bytes; every "valid"
    vector verifies with `cryptography` along its chain to the root; every invalid one
    differs from its base only in the intended way (bit flips: exactly one bit; the others
    are cryptographically valid so that only the named check can fail).

How to run (from the repository root)
    PY=$(bash ../shared/oracle/setup.sh | tail -n1); $PY -m pip install cryptography
    $PY codec/codegen/make_signed_vectors.py            (write the file)
    $PY codec/codegen/make_signed_vectors.py --check    (exit 1 if the committed file differs)
"""
import hashlib
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vector_file  # noqa: E402  (beside this script)
from datetime import datetime, timezone

try:
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.hazmat.primitives.asymmetric.utils import (
        decode_dss_signature, encode_dss_signature)
    from cryptography.exceptions import InvalidSignature
    import cryptography
except ImportError:
    sys.exit('make_signed_vectors.py needs the `cryptography` package in the oracle venv:\n'
             '    PY=$(bash ../shared/oracle/setup.sh | tail -n1); $PY -m pip install cryptography')
try:
    ec.ECDSA(hashes.SHA256(), deterministic_signing=True)
except TypeError:
    sys.exit('make_signed_vectors.py needs cryptography >= 42 (RFC 6979 deterministic ECDSA);'
             ' found %s:\n    $PY -m pip install -U cryptography' % cryptography.__version__)
try:
    from pycrate_asn1dir import ITS_IEEE1609_2 as I2
except ImportError:
    sys.exit('pycrate is missing: run with the oracle python, $(bash ../shared/oracle/setup.sh)')

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, '..', '..'))
OUT = os.path.join(REPO, 'codec', 'tests', 'vectors', 'ieee1609dot2_signed.jsonl')
FRAMES = os.path.join(REPO, 'codec', 'tests', 'vectors', 'oracle_vectors.jsonl')

# IEEE 1609.2 Psid is an INTEGER: TIM 131 and MAP 2113687 (their IEEE 1609.12 p-encoded
# octets are 80-03 and E0-00-00-17; PSID_MISREAD_* are those octets read as numbers, what a
# verifier that mixes the two forms would put in a header or certificate). BSM is 32.
PSID_TIM, PSID_MAP, PSID_WRONG = 131, 2113687, 32
PSID_MISREAD_TIM, PSID_MISREAD_MAP = 0x8003, 0xE0000017
LEAP_SECONDS_SINCE_2004 = 5
EPOCH = datetime(2004, 1, 1, tzinfo=timezone.utc)
SITE_LAT, SITE_LON, SITE_ELEV = 421234567, -837654321, 2710   # as make_vectors.py
REGION_RADIUS_M = 5000
# The verifier's security profile for MAP and TIM (the OBU's defaults): a generation time at
# most FUTURE_TOLERANCE ahead of its clock; with an expiryTime the message is relevant until
# it (plus FUTURE_TOLERANCE), if generation to expiry is at most MAX_LIFETIME; without one,
# for PAST_WINDOW after its generation; a byte-identical copy of an accepted message is a
# repeat (accepted).
FUTURE_TOLERANCE_US = 5 * 1000000
PAST_WINDOW_US = 30 * 1000000
MAX_LIFETIME_US = 7 * 24 * 3600 * 1000000
HOUR_US = 3600 * 1000000
TIM_FRAME, MAP_FRAME = 'tim_work_zone_left_lane_closed', 'map_work_zone'
# The cancel of TIM_FRAME's first data frame (the same packetID, durationTime 0, msgCnt + 2).
CANCEL_FRAME = 'tim_cancel_zero_duration'

# ============================================================================ P-256 helper
P = 0xffffffff00000001000000000000000000000000ffffffffffffffffffffffff
N = 0xffffffff00000000ffffffffffffffffbce6faada7179e84f3b9cac2fc632551
A = P - 3
G = (0x6b17d1f2e12c4247f8bce6e563a440f277037d812deb33a0f4a13945d898c296,
     0x4fe342e2fe1a7f9b8ee7eb4a7c0f9e162bce33576b315ececbb6406837bf51f5)


def _add(p1, p2):
    if p1 is None:
        return p2
    if p2 is None:
        return p1
    (x1, y1), (x2, y2) = p1, p2
    if x1 == x2 and (y1 + y2) % P == 0:
        return None
    if p1 == p2:
        lam = (3 * x1 * x1 + A) * pow(2 * y1, -1, P) % P
    else:
        lam = (y2 - y1) * pow(x2 - x1, -1, P) % P
    x3 = (lam * lam - x1 - x2) % P
    return x3, (lam * (x1 - x3) - y1) % P


def _mul(k, pt):
    acc = None
    while k:
        if k & 1:
            acc = _add(acc, pt)
        pt = _add(pt, pt)
        k >>= 1
    return acc


def signature_point(pub, e, r, s):
    """R = s^-1 e G + s^-1 r Q, the point whose x is r (checked)."""
    w = pow(s, -1, N)
    q = pub.public_numbers()
    R = _add(_mul(e * w % N, G), _mul(r * w % N, (q.x, q.y)))
    assert R is not None and R[0] % N == r
    return R


# ============================================================================ crypto
def sha256(b):
    return hashlib.sha256(b).digest()


def hashed_id8(cert_coer):
    return sha256(cert_coer)[-8:]


def key(seed):
    """A fixed private key from a fixed seed: d = SHA-256(seed) mod (n - 1) + 1."""
    d = int.from_bytes(sha256(b'make_signed_vectors/' + seed.encode()), 'big') % (N - 1) + 1
    return ec.derive_private_key(d, ec.SECP256R1())


def compressed(pub):
    return pub.public_bytes(serialization.Encoding.X962, serialization.PublicFormat.CompressedPoint)


def curve_point(pub):
    c = compressed(pub)
    return ('compressed-y-0' if c[0] == 2 else 'compressed-y-1', c[1:])


def to_be_signed_input(data_coer, signer_cert_coer):
    """1609.2 5.3.1: SHA-256(data) || SHA-256(signer certificate or empty string)."""
    return sha256(data_coer) + sha256(signer_cert_coer if signer_cert_coer is not None else b'')


def sign(priv, data_coer, signer_cert_coer, form='x-only'):
    msg = to_be_signed_input(data_coer, signer_cert_coer)
    der = priv.sign(msg, ec.ECDSA(hashes.SHA256(), deterministic_signing=True))
    r, s = decode_dss_signature(der)
    if form == 'x-only':
        rsig = ('x-only', r.to_bytes(32, 'big'))
    else:
        e = int.from_bytes(sha256(msg), 'big')
        R = signature_point(priv.public_key(), e, r, s)
        rsig = ('compressed-y-%d' % (R[1] & 1), R[0].to_bytes(32, 'big'))
    return ('ecdsaNistP256Signature', {'rSig': rsig, 'sSig': s.to_bytes(32, 'big')})


def verify(pub, data_coer, signer_cert_coer, signature):
    """Verify a pycrate Signature value; compressed-y rSig is checked to be on the curve and
    to be the point R of the signature."""
    kind, sig = signature
    assert kind == 'ecdsaNistP256Signature'
    form, rx = sig['rSig']
    r, s = int.from_bytes(rx, 'big'), int.from_bytes(sig['sSig'], 'big')
    msg = to_be_signed_input(data_coer, signer_cert_coer)
    try:
        pub.verify(encode_dss_signature(r, s), msg, ec.ECDSA(hashes.SHA256()))
    except InvalidSignature:
        return False
    if form.startswith('compressed'):
        R = signature_point(pub, int.from_bytes(sha256(msg), 'big'), r, s)
        return R[1] & 1 == int(form[-1])
    return True


def public_from_point(point):
    form, x = point
    prefix = {'compressed-y-0': b'\x02', 'compressed-y-1': b'\x03'}[form]
    return ec.EllipticCurvePublicKey.from_encoded_point(ec.SECP256R1(), prefix + x)


# ============================================================================ time
def time32(iso):
    dt = datetime.fromisoformat(iso).replace(tzinfo=timezone.utc)
    return int((dt - EPOCH).total_seconds()) + LEAP_SECONDS_SINCE_2004


def time64(iso):
    return time32(iso) * 1000000


GEN = time64('2025-06-17T12:32:41')          # the generation time of every frame (inside
                                             # the TIM's window: 12:00 for 60 minutes)
EXPIRY = GEN + 60 * 1000000                  # expiryTime: one minute later
NOW = GEN + 2 * 1000000                      # the verifier's clock for the normal cases

# ============================================================================ ASN.1
CERT = I2.Ieee1609Dot2.Certificate
DATA = I2.Ieee1609Dot2.Ieee1609Dot2Data
TBS_DATA = I2.Ieee1609Dot2.ToBeSignedData
TBS_CERT = I2.Ieee1609Dot2.ToBeSignedCertificate


def coer(asn, val):
    asn.set_val(val)
    b = asn.to_coer()
    asn.from_coer(b)
    back = asn.get_val()        # DEFAULT members come back filled in: compare by re-encoding
    asn.set_val(back)
    assert asn.to_coer() == b, 'pycrate COER round trip'
    return b


def circle(lat, lon, radius):
    return ('circularRegion', {'center': {'latitude': lat, 'longitude': lon}, 'radius': radius})


class Cert:
    def __init__(self, name, priv, val, coer_bytes):
        self.name, self.priv, self.val, self.coer = name, priv, val, coer_bytes
        self.id8 = hashed_id8(coer_bytes)


def rectangle(lat, lon, half_e7):
    """One rectangle of +-half_e7 (1e-7 degrees) around (lat, lon)."""
    return ('rectangularRegion', [{'northWest': {'latitude': lat + half_e7,
                                                 'longitude': lon - half_e7},
                                   'southEast': {'latitude': lat - half_e7,
                                                 'longitude': lon + half_e7}}])


def polygon(lat, lon, r_e7):
    """A quadrilateral (a kite, not a rectangle) around (lat, lon)."""
    return ('polygonalRegion', [{'latitude': lat + r_e7, 'longitude': lon},
                                {'latitude': lat, 'longitude': lon + 2 * r_e7},
                                {'latitude': lat - r_e7, 'longitude': lon},
                                {'latitude': lat, 'longitude': lon - r_e7}])


def make_cert(name, seed, issuer, start, duration, app=None, issue=None, min_chain=1,
              region=True):
    """An explicit certificate. issuer None: self-signed (issuer `self`, sha256)."""
    priv = key(seed)
    tbs = {'id': ('name', name), 'cracaId': b'\0\0\0', 'crlSeries': 0,
           'validityPeriod': {'start': time32(start), 'duration': duration},
           'verifyKeyIndicator': ('verificationKey',
                                  ('ecdsaNistP256', curve_point(priv.public_key())))}
    if region is True:
        tbs['region'] = circle(SITE_LAT, SITE_LON, REGION_RADIUS_M)
    elif region:
        tbs['region'] = region
    if app:
        tbs['appPermissions'] = [{'psid': p} for p in app]
    if issue:
        perm = {'subjectPermissions': ('all', 0)}
        if min_chain != 1:
            perm['minChainLength'] = min_chain
        tbs['certIssuePermissions'] = [perm]
    tbs_coer = coer(TBS_CERT, tbs)
    signer = issuer.priv if issuer else priv
    val = {'version': 3, 'type': 'explicit',
           'issuer': ('sha256AndDigest', issuer.id8) if issuer else ('self', 'sha256'),
           'toBeSigned': tbs,
           'signature': sign(signer, tbs_coer, issuer.coer if issuer else None)}
    return Cert(name, priv, val, coer(CERT, val))


def pki():
    c = {}
    c['root'] = make_cert('root.workzone.example', 'root', None, '2025-01-01T00:00:00',
                          ('years', 10), issue=True, min_chain=2, region=False)
    c['ca'] = make_cert('ca.workzone.example', 'ca', c['root'], '2025-01-01T00:00:00',
                        ('years', 5), issue=True, region=False)
    c['rsu'] = make_cert('rsu-17.workzone.example', 'rsu', c['ca'], '2025-06-01T00:00:00',
                         ('hours', 24 * 30), app=[PSID_TIM, PSID_MAP])
    c['rsu_expired'] = make_cert('rsu-17.workzone.example', 'rsu', c['ca'],
                                 '2025-05-01T00:00:00', ('hours', 24 * 30), app=[PSID_TIM, PSID_MAP])
    c['rsu_not_yet'] = make_cert('rsu-17.workzone.example', 'rsu', c['ca'],
                                 '2025-07-01T00:00:00', ('hours', 24 * 30), app=[PSID_TIM, PSID_MAP])
    c['evil_root'] = make_cert('root.workzone.example', 'evil-root', None,
                               '2025-01-01T00:00:00', ('years', 10), issue=True,
                               min_chain=2, region=False)
    c['evil_ca'] = make_cert('ca.workzone.example', 'evil-ca', c['evil_root'],
                             '2025-01-01T00:00:00', ('years', 5), issue=True, region=False)
    c['evil_rsu'] = make_cert('rsu-17.workzone.example', 'evil-rsu', c['evil_ca'],
                              '2025-06-01T00:00:00', ('hours', 24 * 30), app=[PSID_TIM, PSID_MAP])
    # The same RSU with a rectangle (+-0.05 degrees) or a kite-shaped polygon as its region.
    c['rsu_rect'] = make_cert('rsu-17.workzone.example', 'rsu', c['ca'], '2025-06-01T00:00:00',
                              ('hours', 24 * 30), app=[PSID_TIM, PSID_MAP],
                              region=rectangle(SITE_LAT, SITE_LON, 500000))
    c['rsu_poly'] = make_cert('rsu-17.workzone.example', 'rsu', c['ca'], '2025-06-01T00:00:00',
                              ('hours', 24 * 30), app=[PSID_TIM, PSID_MAP],
                              region=polygon(SITE_LAT, SITE_LON, 500000))
    # The same RSU as a verifier that mixes the two PSID forms would certify it.
    c['rsu_misread'] = make_cert('rsu-17.workzone.example', 'rsu', c['ca'],
                                 '2025-06-01T00:00:00', ('hours', 24 * 30),
                                 app=[PSID_MISREAD_TIM, PSID_MISREAD_MAP])
    c['rsu_implicit'] = make_implicit_cert('rsu-18.workzone.example', 'rsu-implicit', c['ca'],
                                           '2025-06-01T00:00:00', ('hours', 24 * 30),
                                           [PSID_TIM, PSID_MAP])
    return c


# ============================================================================ ECQV
# Implicit certificates: Elliptic Curve Qu-Vanstone (SEC 4 v1.0, 3.4 / 3.5 / 3.6) as profiled
# by IEEE 1609.2-2016 5.3.2. The hash e is computed like a signature's hash (5.3.1), with the
# implicit certificate's ToBeSignedCertificate as data and the issuer's certificate as signer:
#     e = int( SHA-256( SHA-256(tbsCertificate COER) || SHA-256(issuer certificate COER) ) ) mod n
# Here e is the whole 256-bit digest as a big-endian integer, reduced mod n. Plain SEC 4
# (2.3, Hn) would take the leftmost floor(log2 n) = 255 bits (digest >> 1), a different e and
# so a different key: a verifier that reconstructs another key has made that choice. The
# 1609.2 text itself was not available while writing this; the full-digest reading follows
# published 1609.2 implementations (e.g. public-key reconstruction as H(CertU) * P_U + Q_CA
# with H(CertU) the whole digest, and reference scripts that call it the non-SEC-4 variant).
# Treat it as the one assumption of these vectors that the standard should confirm.
#   requester: k_U, R_U = k_U G        CA: ephemeral k, P_U = R_U + k G (the reconstructionValue)
#   CA -> requester: r = e k + d_CA mod n      requester: d_U = e k_U + r mod n
#   any verifier: Q_U = e P_U + Q_CA
# Self-check: Q_U == d_U G, and a signature made with d_U verifies with Q_U (cryptography).
def point_bytes(pt):
    return bytes([2 + (pt[1] & 1)]) + pt[0].to_bytes(32, 'big')


def priv_int(priv):
    return priv.private_numbers().private_value


def make_implicit_cert(name, seed, issuer, start, duration, app):
    k_u = priv_int(key(seed + '/request'))
    k = priv_int(key(seed + '/ca-ephemeral'))
    p_u = _add(_mul(k_u, G), _mul(k, G))
    pb = point_bytes(p_u)
    tbs = {'id': ('name', name), 'cracaId': b'\0\0\0', 'crlSeries': 0,
           'validityPeriod': {'start': time32(start), 'duration': duration},
           'region': circle(SITE_LAT, SITE_LON, REGION_RADIUS_M),
           'appPermissions': [{'psid': p} for p in app],
           'verifyKeyIndicator': ('reconstructionValue',
                                  ('compressed-y-%d' % (pb[0] - 2), pb[1:]))}
    tbs_coer = coer(TBS_CERT, tbs)
    e = int.from_bytes(sha256(to_be_signed_input(tbs_coer, issuer.coer)), 'big') % N
    r = (e * k + priv_int(issuer.priv)) % N
    d_u = (e * k_u + r) % N
    priv = ec.derive_private_key(d_u, ec.SECP256R1())
    val = {'version': 3, 'type': 'implicit', 'issuer': ('sha256AndDigest', issuer.id8),
           'toBeSigned': tbs}
    cert = Cert(name, priv, val, coer(CERT, val))
    # self-check: the verifier's reconstruction gives the requester's public key
    q = reconstruct_public(cert, issuer)
    assert compressed(q) == compressed(priv.public_key())
    probe = sign(priv, b'ecqv self-check', None)
    assert verify(q, b'ecqv self-check', None, probe)
    return cert


def reconstruct_public(cert, issuer):
    """Q_U = e P_U + Q_CA, from the certificate and its issuer only."""
    tbs = cert.val['toBeSigned']
    form, x = tbs['verifyKeyIndicator'][1]
    p_u = public_from_point((form, x)).public_numbers()
    e = int.from_bytes(sha256(to_be_signed_input(coer(TBS_CERT, tbs), issuer.coer)),
                       'big') % N
    qca = issuer.priv.public_key().public_numbers()
    q = _add(_mul(e, (p_u.x, p_u.y)), (qca.x, qca.y))
    return ec.EllipticCurvePublicNumbers(q[0], q[1], ec.SECP256R1()).public_key()


def unsecured(frame):
    return {'protocolVersion': 3, 'content': ('unsecuredData', frame)}


def location(lat=SITE_LAT + 1000, lon=SITE_LON - 2000, elev=SITE_ELEV):
    return {'latitude': lat, 'longitude': lon, 'elevation': elev}


def signed(frame, psid, signer_kind, cert, chain=None, form='x-only', gen=GEN,
           expiry=EXPIRY, loc=None, priv=None):
    """An Ieee1609Dot2Data with SignedData; returns (value, tbs_coer, signer_cert_coer)."""
    header = {'psid': psid, 'generationTime': gen, 'generationLocation': loc or location()}
    if expiry is not None:
        header['expiryTime'] = expiry
    tbs = {'payload': {'data': unsecured(frame)}, 'headerInfo': header}
    tbs_coer = coer(TBS_DATA, tbs)
    if signer_kind == 'self':
        signer, signer_coer = ('self', 0), None
    elif signer_kind == 'digest':
        signer, signer_coer = ('digest', cert.id8), cert.coer
    else:
        signer, signer_coer = ('certificate', [c.val for c in chain]), cert.coer
    sig = sign(priv or cert.priv, tbs_coer, signer_coer, form)
    val = {'protocolVersion': 3, 'content': ('signedData', {
        'hashId': 'sha256', 'tbsData': tbs, 'signer': signer, 'signature': sig})}
    return val, tbs_coer, signer_coer


# ============================================================================ vectors
def frames():
    by_name = {}
    with open(FRAMES, encoding='ascii') as f:
        for line in f:
            v = json.loads(line)
            by_name[v['name']] = bytes.fromhex(v['uper'])
    tims = sorted(n for n in by_name if n.startswith('tim_work_zone'))
    maps = sorted(n for n in by_name if n.startswith('map_work_zone'))
    tim = by_name.get(TIM_FRAME) or by_name[tims[0] if tims else sorted(
        n for n in by_name if n.startswith('tim'))[0]]
    mp = by_name.get(MAP_FRAME) or by_name[maps[0] if maps else sorted(
        n for n in by_name if n.startswith('map'))[0]]
    return tim, mp, by_name[CANCEL_FRAME]


# WSMP (IEEE 1609.3-2016 8.3): N-header 0x0B (subtype 0 null networking, option indicator 1,
# version 3) with one WAVE information element (channel number, id 15, length 1, 172), TPID
# 0, the T-header's p-encoded PSID (IEEE 1609.12), the WSM length (one octet below 128,
# else two: 10xxxxxx xxxxxxxx), the data. The p-encoded octets are written out here.
P_TIM, P_MAP, P_BSM = bytes([0x80, 0x03]), bytes([0xE0, 0x00, 0x00, 0x17]), bytes([0x20])
WSMP_MISMATCH = 'WSMP PSID does not match the message'


def wsmp(psid_octets, data):
    n = len(data)
    assert n < 0x4000
    length = bytes([n]) if n < 128 else bytes([0x80 | (n >> 8), n & 0xff])
    return bytes([0x0B, 0x01, 0x0F, 0x01, 172, 0x00]) + psid_octets + length + data


def flip_bit(b, octet, bit):
    b = bytearray(b)
    b[octet] ^= 0x80 >> bit
    return bytes(b)


def make_all():
    tim, mp, cancel = frames()
    c = pki()
    anchors = {'root': c['root'].coer.hex(), 'ca': c['ca'].coer.hex()}
    rsu = c['rsu']
    vectors = {}

    def add(name, case, expect, val, kind, cert, chain, frame, psid, now=NOW, form='x-only',
            **extra):
        data = coer(DATA, val)
        hi = val['content'][1]['tbsData']['headerInfo']
        v = {'name': name, 'case': case, 'expect': expect, 'coer': data.hex(),
             'signer': kind, 'psid': psid, 'generation_time': hi['generationTime'],
             'expiry_time': hi.get('expiryTime'),
             'generation_location': hi['generationLocation'],
             'frame': frame.hex(), 'trust_anchors': anchors, 'now': now,
             'future_tolerance_us': FUTURE_TOLERANCE_US, 'past_window_us': PAST_WINDOW_US,
             'max_lifetime_us': MAX_LIFETIME_US, 'rsig_form': form,
             'known_certs': [cert.coer.hex()] if kind == 'digest' else []}
        if kind == 'self':
            v['self_public_key'] = compressed(cert.priv.public_key()).hex()
        v.update(extra)
        assert name not in vectors
        vectors[name] = (v, val, cert, chain)
        return data

    # valid: every signer kind, both rSig forms, TIM and MAP
    valid = {}
    for msg, frame, psid in (('tim', tim, PSID_TIM), ('map', mp, PSID_MAP)):
        for kind, chain in (('digest', None), ('certificate', [rsu]),
                            ('certificate-chain', [rsu, c['ca']]), ('self', None)):
            for form in ('x-only', 'compressed-y'):
                name = 'valid_%s_%s_%s' % (msg, kind.replace('-', '_'), form.replace('-', '_'))
                sk = 'certificate' if kind.startswith('certificate') else kind
                val, _, _ = signed(frame, psid, sk, rsu, chain, form)
                valid[name] = add(name, 'valid', 'valid', val, kind, rsu, chain, frame, psid,
                                  form=form)
    imp = c['rsu_implicit']
    for kind, chain in (('digest', None), ('certificate', [imp]),
                        ('certificate-chain', [imp, c['ca']])):
        for form in ('x-only', 'compressed-y'):
            name = 'valid_tim_implicit_%s_%s' % (kind.replace('-', '_'), form.replace('-', '_'))
            sk = 'certificate' if kind.startswith('certificate') else kind
            val, _, _ = signed(tim, PSID_TIM, sk, imp, chain, form)
            add(name, 'valid (implicit certificate, ECQV)', 'valid', val, kind, imp, chain,
                tim, PSID_TIM, form=form, certificate_type='implicit',
                reconstructed_public_key=compressed(reconstruct_public(imp, c['ca'])).hex())
    base = 'valid_tim_certificate_x_only'
    base_val = vectors[base][1]
    base_coer = valid[base]

    # IEEE 1609.3 WSMP v3 around the base (signed) and around its bare frame, laid out here
    # from the standard's figures: the T-header PSID must be the message's
    vectors[base][0]['wsmp'] = [
        {'bytes': wsmp(P_TIM, base_coer).hex(), 'expect': 'valid'},
        {'bytes': wsmp(P_MAP, base_coer).hex(), 'expect': WSMP_MISMATCH},
        {'bytes': wsmp(P_TIM, tim).hex(), 'expect': 'valid (unsigned)'},
        {'bytes': wsmp(P_BSM, tim).hex(), 'expect': WSMP_MISMATCH},
    ]
    # payload bit flipped: one bit of the MessageFrame inside, the signature unchanged
    off = base_coer.find(tim)
    assert off > 0 and base_coer.count(tim) == 1
    bad = flip_bit(base_coer, off + 5, 3)
    DATA.from_coer(bad)
    add('payload_bit_flipped', 'payload bit flipped', 'signature does not verify',
        DATA.get_val(), 'certificate', rsu, [rsu], tim, PSID_TIM, differs_from=base,
        note='the frame member is the flipped frame as it sits in the bytes')
    vectors['payload_bit_flipped'][0]['frame'] = bad[off:off + len(tim)].hex()
    # signature bit flipped: one bit of sSig
    s = base_val['content'][1]['signature'][1]['sSig']
    off_s = base_coer.rfind(s)
    bad = flip_bit(base_coer, off_s + 31, 7)
    DATA.from_coer(bad)
    add('signature_bit_flipped', 'signature bit flipped', 'signature does not verify',
        DATA.get_val(), 'certificate', rsu, [rsu], tim, PSID_TIM, differs_from=base)
    # wrong PSID: signed correctly, header PSID 0x20 not in the certificate's appPermissions
    val, _, _ = signed(tim, PSID_WRONG, 'certificate', rsu, [rsu])
    add('wrong_psid', 'wrong PSID', 'PSID not permitted by the signer certificate', val,
        'certificate', rsu, [rsu], tim, PSID_WRONG, differs_from=base)
    # message expired: generated a minute before now, expired 30 s ago (past the tolerance)
    val, _, _ = signed(tim, PSID_TIM, 'certificate', rsu, [rsu], gen=NOW - 60 * 1000000,
                       expiry=NOW - 30 * 1000000)
    add('message_expired', 'message expired', 'message past its expiryTime', val,
        'certificate', rsu, [rsu], tim, PSID_TIM, differs_from=base)
    # the misread PSIDs: a certificate granting 32771 and a header carrying it, signed
    # correctly; 32771 is no message the OBU uses (TIM is 131)
    mis = c['rsu_misread']
    val, _, _ = signed(tim, PSID_MISREAD_TIM, 'certificate', mis, [mis, c['ca']])
    add('misread_psid', 'misread PSID (p-encoded octets as the integer)',
        'PSID is not the message type\'s', val, 'certificate-chain', mis, [mis, c['ca']], tim,
        PSID_MISREAD_TIM, differs_from=CHAIN_BASE)
    # the deposited-TIM pattern: signed two hours before now, relevant for a day (MAP too)
    for msg, frame, psid in (('tim', tim, PSID_TIM), ('map', mp, PSID_MAP)):
        gen = NOW - 2 * HOUR_US
        val, _, _ = signed(frame, psid, 'certificate', rsu, [rsu], gen=gen,
                           expiry=gen + 24 * HOUR_US)
        add('valid_%s_signed_once_expiry_ahead' % msg,
            'valid (signed once with an expiry time, generated two hours ago)', 'valid', val,
            'certificate', rsu, [rsu], frame, psid)
    # generation time after the expiry time
    val, _, _ = signed(tim, PSID_TIM, 'certificate', rsu, [rsu], expiry=GEN - 1000000)
    add('expiry_before_generation', 'expiry time before generation time',
        'expiry time not after generation time', val, 'certificate', rsu, [rsu], tim,
        PSID_TIM, differs_from=base)
    # lifetime over the 7-day cap: expiry 8 days after generation
    val, _, _ = signed(tim, PSID_TIM, 'certificate', rsu, [rsu], expiry=GEN + 8 * 24 * HOUR_US)
    add('lifetime_over_cap', 'lifetime over the cap', 'lifetime longer than allowed', val,
        'certificate', rsu, [rsu], tim, PSID_TIM, differs_from=base)
    # a digest signer before its certificate was seen (known_certs empty)
    val, _, _ = signed(tim, PSID_TIM, 'digest', rsu)
    add('digest_signer_not_seen', 'digest signer before its certificate was seen',
        'signer certificate not known', val, 'digest', rsu, None, tim, PSID_TIM,
        differs_from='valid_tim_digest_x_only')
    vectors['digest_signer_not_seen'][0]['known_certs'] = []
    # certificate expired / not yet valid (validity period ends before / starts after GEN)
    for nm, ck, why in (('certificate_expired', 'rsu_expired',
                         'signer certificate expired'),
                        ('certificate_not_yet_valid', 'rsu_not_yet',
                         'signer certificate not yet valid')):
        cert = c[ck]
        val, _, _ = signed(tim, PSID_TIM, 'certificate', cert, [cert, c['ca']])
        add(nm, nm.replace('_', ' '), why, val, 'certificate-chain', cert, [cert, c['ca']],
            tim, PSID_TIM, differs_from=CHAIN_BASE)
    # untrusted root: a full, correct chain to another root with the same names
    ev = c['evil_rsu']
    val, _, _ = signed(tim, PSID_TIM, 'certificate', ev, [ev, c['evil_ca']])
    add('untrusted_root', 'chain to an untrusted root', 'chain does not reach a trust anchor',
        val, 'certificate-chain', ev, [ev, c['evil_ca']], tim, PSID_TIM,
        untrusted_root=c['evil_root'].coer.hex(), differs_from=CHAIN_BASE)
    # region miss: generationLocation 0.2 degrees (about 22 km) north of the 5 km circle
    val, _, _ = signed(tim, PSID_TIM, 'certificate', rsu, [rsu],
                       loc=location(SITE_LAT + 2000000))
    add('region_miss', 'region miss', 'generation location outside the certificate region',
        val, 'certificate', rsu, [rsu], tim, PSID_TIM, differs_from=base)
    # rectangle and polygon regions: inside (valid) and outside (region miss). The outside
    # points: 0.08 degrees north of the rectangle's centre (its half side is 0.05); inside
    # the polygon's bounding box but outside the kite (east of its south-east edge).
    for shape, ck, outside in (('rectangle', 'rsu_rect', location(SITE_LAT + 800000)),
                               ('polygon', 'rsu_poly', location(SITE_LAT - 400000,
                                                                SITE_LON + 800000))):
        cert = c[ck]
        val, _, _ = signed(tim, PSID_TIM, 'certificate', cert, [cert])
        add('valid_tim_%s_region' % shape, 'valid (%s region)' % shape, 'valid', val,
            'certificate', cert, [cert], tim, PSID_TIM)
        val, _, _ = signed(tim, PSID_TIM, 'certificate', cert, [cert], loc=outside)
        add('region_miss_%s' % shape, 'region miss (%s)' % shape,
            'generation location outside the certificate region', val, 'certificate', cert,
            [cert], tim, PSID_TIM, differs_from='valid_tim_%s_region' % shape)
    # generation time in the future / too old, by the verifier's clock
    val, _, _ = signed(tim, PSID_TIM, 'certificate', rsu, [rsu])
    add('generation_time_future', 'generation time in the future',
        'generation time beyond the future tolerance', val, 'certificate', rsu, [rsu], tim,
        PSID_TIM, now=GEN - 5 * 60 * 1000000, differs_from=base,
        note='valid bytes (same as %s); the verifier clock is 5 min before generation' % base)
    val, _, _ = signed(tim, PSID_TIM, 'certificate', rsu, [rsu], expiry=None)
    add('generation_time_too_old', 'generation time too old',
        'generation time older than the past window', val, 'certificate', rsu, [rsu], tim,
        PSID_TIM, now=GEN + 10 * 60 * 1000000, differs_from=base,
        note='no expiryTime (signed per transmission), generated 10 minutes before the clock')
    # repeat: the same valid frame twice (an RSU repeating what it was given)
    val, _, _ = signed(tim, PSID_TIM, 'certificate', rsu, [rsu])
    add('repeat_1_first', 'repeat', 'valid', val, 'certificate', rsu, [rsu], tim, PSID_TIM,
        pair='repeat', differs_from=base)
    add('repeat_2_second', 'repeat', 'valid (repeat)', val, 'certificate', rsu, [rsu], tim,
        PSID_TIM, pair='repeat', differs_from=base,
        note='identical bytes to repeat_1_first, received after it')
    # the signed cancel of the base TIM's first data frame, a second after it: received after
    # the base, the base again is superseded (the OBU's tests)
    val, _, _ = signed(cancel, PSID_TIM, 'certificate', rsu, [rsu], gen=GEN + 1000000,
                       expiry=EXPIRY + 1000000)
    add('signed_cancel_of_base', 'valid (the cancel of %s)' % base, 'valid', val,
        'certificate', rsu, [rsu], cancel, PSID_TIM,
        note='%s with durationTime 0, the same packetID as %s' % (CANCEL_FRAME, TIM_FRAME))
    # superseded: the same TIM signed at two times, the newer received first; the older is
    # valid on its own (within the past window) and must be refused after the newer
    for name, gen, expect in (('superseded_1_newer', NOW - 1000000, 'valid'),
                              ('superseded_2_older', NOW - 10 * 1000000,
                               'superseded by a newer version')):
        val, _, _ = signed(tim, PSID_TIM, 'certificate', rsu, [rsu], gen=gen, expiry=None)
        add(name, 'superseded', expect, val, 'certificate', rsu, [rsu], tim, PSID_TIM,
            pair='superseded',
            note='the same TIM (same packetID / msgId); received in name order')
    return vectors, c


# ============================================================================ self-check
CHAIN_BASE = 'valid_tim_certificate_chain_x_only'
# What each invalid vector may differ in from its base ("differs_from"), beyond the signature
# (re-signed, so it differs whenever anything signed does): headerInfo members, 'signer'.
INTENDED = {
    'wrong_psid': {'psid'}, 'message_expired': {'generationTime', 'expiryTime'},
    'certificate_expired': {'signer'}, 'certificate_not_yet_valid': {'signer'},
    'untrusted_root': {'signer'}, 'region_miss': {'generationLocation'},
    'generation_time_future': set(), 'generation_time_too_old': {'expiryTime'},
    'repeat_1_first': set(), 'repeat_2_second': set(),
    'misread_psid': {'psid', 'signer'},
    'expiry_before_generation': {'expiryTime'}, 'lifetime_over_cap': {'expiryTime'},
    'digest_signer_not_seen': set(),
    'region_miss_rectangle': {'generationLocation'}, 'region_miss_polygon': {'generationLocation'},
}


def differences(a, b):
    sa, sb = a['content'][1], b['content'][1]
    d = {k for k in set(sa['tbsData']['headerInfo']) | set(sb['tbsData']['headerInfo'])
         if sa['tbsData']['headerInfo'].get(k) != sb['tbsData']['headerInfo'].get(k)}
    if sa['tbsData']['payload'] != sb['tbsData']['payload']:
        d.add('payload')
    if sa['signer'] != sb['signer']:
        d.add('signer')
    if sa['hashId'] != sb['hashId'] or a['protocolVersion'] != b['protocolVersion']:
        d.add('envelope')
    return d


def check_intended(vectors, c):
    for name, want in INTENDED.items():
        v, val = vectors[name][0], vectors[name][1]
        base = vectors[v['differs_from']]
        DATA.from_coer(bytes.fromhex(base[0]['coer']))
        bval = DATA.get_val()
        DATA.from_coer(bytes.fromhex(v['coer']))
        got = differences(DATA.get_val(), bval)
        assert got == want, (name, got, want)
        if not want:
            assert v['coer'] == base[0]['coer'], name
        for k in ('trust_anchors', 'future_tolerance_us', 'past_window_us', 'max_lifetime_us',
                  'rsig_form'):
            assert v[k] == base[0][k], (name, k)
        if name not in ('generation_time_future', 'generation_time_too_old'):
            assert v['now'] == base[0]['now'], name
    # the expired / not-yet-valid RSU certificates differ from the good one only in validity
    good = c['rsu'].val['toBeSigned']
    for ck in ('rsu_expired', 'rsu_not_yet'):
        t = c[ck].val['toBeSigned']
        assert {k for k in set(t) | set(good) if t.get(k) != good.get(k)} == {'validityPeriod'}
        vp = t['validityPeriod']
        end = vp['start'] + vp['duration'][1] * 3600
        assert (end * 1000000 < GEN) if ck == 'rsu_expired' else (vp['start'] * 1000000 > GEN)
    # region: the normal location inside the circle, the region-miss one outside it
    def dist_m(loc):
        import math
        dlat = (loc['latitude'] - SITE_LAT) * 1e-7 * 111195.0
        dlon = (loc['longitude'] - SITE_LON) * 1e-7 * 111195.0 * math.cos(
            math.radians(SITE_LAT * 1e-7))
        return math.hypot(dlat, dlon)
    assert dist_m(vectors['region_miss'][0]['generation_location']) > 4 * REGION_RADIUS_M
    assert dist_m(location()) < REGION_RADIUS_M / 10
    # rectangle and polygon: inside / outside by plain comparisons and the even-odd rule
    def in_rect(loc, reg):
        r = reg[1][0]
        return (r['southEast']['latitude'] <= loc['latitude'] <= r['northWest']['latitude']
                and r['northWest']['longitude'] <= loc['longitude'] <= r['southEast']['longitude'])

    def in_poly(loc, reg):
        pts, inside = reg[1], False
        y, x = loc['latitude'], loc['longitude']
        for i, a in enumerate(pts):
            b = pts[(i + 1) % len(pts)]
            if (a['latitude'] > y) != (b['latitude'] > y):
                cross = a['longitude'] + (y - a['latitude']) * (
                    b['longitude'] - a['longitude']) / (b['latitude'] - a['latitude'])
                if cross > x:
                    inside = not inside
        return inside
    for shape, ck, test in (('rectangle', 'rsu_rect', in_rect), ('polygon', 'rsu_poly', in_poly)):
        reg = c[ck].val['toBeSigned']['region']
        assert test(vectors['valid_tim_%s_region' % shape][0]['generation_location'], reg)
        assert not test(vectors['region_miss_%s' % shape][0]['generation_location'], reg)
    # clocks: the profile's time rules (written out here from their statement) fail for the
    # time cases with the named reason, and for no other vector
    for v, _, _, _ in vectors.values():
        got = time_verdict(v)
        if v['name'] in TIME_CASES:
            assert got == v['expect'], (v['name'], got)
        else:
            assert got is None, (v['name'], got)
    gp = good['validityPeriod']
    assert gp['start'] * 1000000 < GEN < (gp['start'] + gp['duration'][1] * 3600) * 1000000


TIME_CASES = {'generation_time_future', 'generation_time_too_old', 'message_expired',
              'expiry_before_generation', 'lifetime_over_cap'}


def time_verdict(v):
    """The time rule that fails for vector v, in words, or None."""
    gen, exp, now = v['generation_time'], v['expiry_time'], v['now']
    if exp is not None:
        if gen >= exp:
            return 'expiry time not after generation time'
        if exp - gen > v['max_lifetime_us']:
            return 'lifetime longer than allowed'
    if gen > now + v['future_tolerance_us']:
        return 'generation time beyond the future tolerance'
    if exp is not None:
        if now > exp + v['future_tolerance_us']:
            return 'message past its expiryTime'
    elif now - gen > v['past_window_us']:
        return 'generation time older than the past window'
    return None


def check_chain(chain_certs, root):
    """Each certificate's signature verifies with its issuer's key, ending at root."""
    for cert in chain_certs:
        tbs_coer = coer(TBS_CERT, cert.val['toBeSigned'])
        kind, id8 = cert.val['issuer']
        issuer = root if kind == 'sha256AndDigest' and id8 == root.id8 else None
        if issuer is None:
            issuer = next((x for x in chain_certs if x.id8 == id8), None)
        assert issuer is not None, cert.name
        if cert.val['type'] == 'implicit':      # no signature: checked by reconstruction
            assert 'signature' not in cert.val
            continue
        pub = public_from_point(issuer.val['toBeSigned']['verifyKeyIndicator'][1][1])
        assert verify(pub, tbs_coer, issuer.coer, cert.val['signature']), cert.name
    rp = public_from_point(root.val['toBeSigned']['verifyKeyIndicator'][1][1])
    assert verify(rp, coer(TBS_CERT, root.val['toBeSigned']), None, root.val['signature'])


def self_check(vectors, c):
    for name, (v, val, cert, chain) in vectors.items():
        data = bytes.fromhex(v['coer'])
        DATA.from_coer(data)
        got = DATA.get_val()
        assert DATA.to_coer() == data, name
        sd = got['content'][1]
        tbs_coer = coer(TBS_DATA, sd['tbsData'])
        signer_coer = None if sd['signer'][0] == 'self' else cert.coer
        if cert.val['type'] == 'implicit':
            pub = reconstruct_public(cert, c['ca'])     # the verifier's view, no private key
            assert compressed(pub).hex() == v['reconstructed_public_key'], name
        else:
            pub = cert.priv.public_key()
        ok = verify(pub, tbs_coer, signer_coer, sd['signature'])
        inner = sd['tbsData']['payload']['data']['content'][1]
        assert inner.hex() == v['frame'], name
        if v['expect'] == 'valid' or 'bit flipped' not in v['case']:
            assert ok, name + ': signature must verify'
        else:
            assert not ok, name + ': signature must fail'
            base = bytes.fromhex(vectors[v['differs_from']][0]['coer'])
            diff = sum(bin(a ^ b).count('1') for a, b in zip(data, base))
            assert len(base) == len(data) and diff == 1, name
        if v['expect'] == 'valid':
            if chain:
                check_chain(chain + ([c['ca']] if c['ca'] not in chain else []), c['root'])
            elif v['signer'] == 'digest':
                check_chain([cert, c['ca']], c['root'])
            assert sd['tbsData']['headerInfo']['psid'] in (PSID_TIM, PSID_MAP)
    for w in vectors['valid_tim_certificate_x_only'][0]['wsmp']:
        b = bytes.fromhex(w['bytes'])
        leading_ones = next(i for i in range(5) if not (b[6] << i) & 0x80)
        at = 6 + leading_ones + 1   # the p-encoded PSID's length
        n, at = (b[at], at + 1) if b[at] < 0x80 else (((b[at] & 0x3F) << 8) | b[at + 1], at + 2)
        data = b[at:]
        assert len(data) == n and data in (bytes.fromhex(vectors['valid_tim_certificate_x_only'][0]['coer']),
                        bytes.fromhex(vectors['valid_tim_certificate_x_only'][0]['frame'])), w
    check_intended(vectors, c)
    check_chain([c['evil_rsu'], c['evil_ca']], c['evil_root'])
    try:
        check_chain([c['evil_rsu'], c['evil_ca']], c['root'])
    except AssertionError:
        pass
    else:
        raise SystemExit('untrusted chain verified against the real root')


def make_text():
    vectors, c = make_all()
    self_check(vectors, c)
    lines = [json.dumps(vectors[n][0], sort_keys=True, separators=(',', ':'))
             for n in sorted(vectors)]
    return '\n'.join(lines) + '\n', vectors


def main():
    note = 'cryptography %s' % cryptography.__version__
    return vector_file.run(__doc__.split('\n\n')[0], OUT, REPO, make_text, note=note)


if __name__ == '__main__':
    sys.exit(main())
