"""Solutions the searches once missed, each found by benchmarks/bench_coverage.py's dense check (Levenberg-Marquardt
from random starts on random arms), each arm and target kept here as a case.

* ``island`` (only axes 2, 3, 4 meet: '6R-spherical-middle', searched over q6): SP3 has solutions for q6 only
  on an interval about 0.015 rad wide, less than the search's step (1.5 degrees), and no sample fell inside it:
  the search answered "unreachable" where four solutions exist (search._islands).
* ``twin2d`` (no two axes meet or are parallel: '6R-general', the 2-D search over q1, q2): two of four
  solutions lie 0.0026 rad apart, inside one grid cell; their windings cancel and Newton from the cell found
  one of them (search2d._twins).
* ``odd`` (only axes 5 and 6 meet: '6R-two-intersecting', searched over q1): two solutions 0.07 rad apart,
  one found (solvers_check._paired).

For the last two an odd count told that one was missing: the real solutions of a 6R come in pairs (the
others are complex, in conjugate pairs). Each target is the FK of the solution that was missed (the test's
own POE.fk); checked: it is found, every solution passes FK, the count is even (``twin2d``, ``odd``), and
nothing Levenberg-Marquardt reaches from 300 random starts is missing from ``ik_all``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from armkit.ik.geometric import solvers as G
from armkit.ik.geometric.poe import POE
from armkit.ik.geometric.search2d import gen_six_dof

from test_dense_check import ik_all_misses   # same folder, on pytest's path

ISLAND_H = np.array([[0.5053153615672773, 0.6757777664671428, -0.5366384217634921],
                     [0.04729237999017623, 0.7659360173609043, -0.6411750526214985],
                     [-0.6918896663948987, 0.08534183610622581, -0.7169417413890572],
                     [0.8872417968246721, -0.4347714929497068, -0.1541938484039179],
                     [0.30326317191973284, -0.23578198367482572, -0.9232758551654792],
                     [0.23284351596827574, 0.6478158895760275, 0.7253402444951966]])
ISLAND_P = np.array([[0.05031570840882769, -0.3713389598056643, 0.2822082593913328],
                     [0.18813578117787214, 0.32357461777997404, -0.2454298968218931],
                     [-0.2941806326171596, -0.03957366153247477, -0.23699240663794577],
                     [0.5615439096784283, -0.16900546890998713, 0.2527425888862121],
                     [-0.8605716281267273, -0.40081602865218224, 0.18667076843502353],
                     [1.4472699845353179, 1.2999233750216392, -0.07775770554331046],
                     [-0.015886001604538347, 0.41729972452990793, -0.0614875305375758]])
ISLAND_R_NT = np.array([[0.43198391734457847, 0.806107223621593, 0.4044515288396359],
                        [-0.8728085775357639, 0.486609716312829, -0.037632047113394525],
                        [-0.2271455087287207, -0.3367523244389478, 0.9137848706612168]])
ISLAND_Q_GEN = np.array([-0.9723891439896288, -3.118913592061787, 0.8457404282423275, 1.6313918826583436,
                         0.7101891304933359, 0.29854948072365195])

TWIN2D_H = np.array([[-0.9213647868700736, 0.29742220179060236, -0.25025379796897035],
                     [-0.5773054039433662, 0.30168160467723326, -0.758753372300352],
                     [0.25827941536977667, 0.9122257842244504, -0.3180186506988746],
                     [-0.2338940749567354, 0.8709768175960093, -0.4320797899815044],
                     [-0.0863613154885782, -0.9156521397369646, -0.3925848725845161],
                     [0.5690190430034422, 0.7917123463247308, 0.2222811044070923]])
TWIN2D_P = np.array([[0.027257924665504356, -0.4032826596077723, -0.46923729120820684],
                     [-0.5227075416541064, 0.656956197219959, 1.272311675061557],
                     [1.3817146166332388, 0.19405726103892906, -0.28706965695912756],
                     [-1.6405171793798419, -0.7682694541144741, -0.4929397502693875],
                     [0.47113736032531256, 1.1708621246789042, 0.21651857712773703],
                     [0.1990746381701851, -1.4027747553893075, -0.9974912744590252],
                     [0.3670683468483007, 0.07288533085964766, -0.18487396509383602]])
TWIN2D_R_NT = np.array([[-0.34733397605899013, 0.23041578188455425, 0.9089926713310639],
                        [0.12553620928463755, -0.9491920755655117, 0.28857419122658734],
                        [0.9293006882777478, 0.2143431154531558, 0.3007611338327115]])
TWIN2D_Q_GEN = np.array([1.327448389909279, -1.6874864131362841, -2.8228681407352547, -2.4371807548018305,
                         -0.7085201145803046, 2.795368735760448])

ODD_H = np.array([[-0.3805095955108391, 0.922286535800985, 0.0678232526822186],
                  [-0.9740962392449966, -0.16509279234294566, -0.15453441883659272],
                  [-0.402588038371625, -0.723128045761676, -0.5612563592450301],
                  [0.7627829227962857, 0.6128665020046766, -0.20629314920982592],
                  [0.8320465326101575, -0.18484096931860147, 0.5230032348205642],
                  [0.7241056674329921, 0.30161689393248853, 0.6202404627932131]])
ODD_P = np.array([[0.1604531681599257, -1.5112347516448557, 0.25910697458050486],
                  [0.258970018765712, 0.7599365139806585, 1.024278993797313],
                  [-0.6366300420847565, 0.9635098968014395, -1.6946851528656055],
                  [0.26071377950830926, 0.7125373514353751, 0.3298034392417458],
                  [-0.37687184588931893, -0.32516033699001834, 0.6017357179023125],
                  [-0.3571628327406504, 0.05772249617464109, -0.23222163224858178],
                  [0.19036448111382276, -0.14834616235672315, -0.17676273367628947]])
ODD_R_NT = np.array([[-0.8339556694557925, -0.22927532367423875, 0.5019469766186602],
                     [-0.24271004696833848, -0.6645013469202973, -0.706774216452283],
                     [0.4955903292873738, -0.7112459391062874, 0.49851724104753703]])
ODD_Q_GEN = np.array([-1.0230442061359053, 2.518021161518157, 1.069510402495878, 1.6522080417056144,
                      2.0496860078814287, -1.4080111190816298])

# Found 2026-12-05 by bench_coverage.py with its generator started from 7: a '6R-two-parallel' arm whose search
# over q6 has two folds 0.04 step apart about one sample (a pair of branches born just before it, one of them
# meeting a third branch just after it). The root 0.0004 rad past the sample, on the member that ends, was missed
# (3 of 4 solutions found): the bisection towards that branch's end took the other member of its pair, 0.43 rad
# away, for it. A branch found there must now be nearer to the ending branch than to any other (search._owned).
FOLDS_H = np.array([[-0.25205918078580586,  0.8122088042104001 , -0.5261017275629312 ],
       [ 0.8087409425908648 ,  0.5136844732168402 , -0.28647224953418626],
       [-0.8087409425908648 , -0.5136844732168401 ,  0.28647224953418626],
       [-0.583219964393407  ,  0.5320713762825487 , -0.6138033265417739 ],
       [-0.5068180656392951 , -0.8109861214393147 , -0.29229601292946245],
       [-0.2491344698149082 , -0.8388490961986216 ,  0.48400848107941286]])
FOLDS_P = np.array([[-0.04237323756164602 , -0.3749952554344774  ,  0.3312174186712479  ],
       [ 0.1720134981447186  , -0.4169268946100054  ,  0.33033439814854926 ],
       [-0.9246159976983281  ,  1.2409124494617423  , -0.011105974501626648],
       [ 0.5350747076812208  ,  0.34508965910444156 ,  0.030182670628574826],
       [ 0.479761850389688   , -0.6015929998079861  , -0.1562392168214246  ],
       [-0.041568189807945466, -0.9665993370266114  , -0.9527274549153399  ],
       [-0.21929708604511655 ,  0.2479941670157707  ,  0.28065534894754834 ]])
FOLDS_R_NT = np.array([[ 0.6507205266398742 ,  0.7019298958162763 ,  0.28958110706480117],
       [-0.7265543348419191 ,  0.46476844438096915,  0.5060722197770886 ],
       [ 0.22063905985101726, -0.5397079899974107 ,  0.8124245754536317 ]])
FOLDS_Q_GEN = np.array([ 0.6938870599932141,  3.1020111791457357, -1.6214537902068282,  1.1539553003957899,  1.464142245907862 ,
        0.5763929294965124])

# Found 2026-12-05 by bench_coverage.py --dense-only --seed 7: a '6R-two-parallel' arm whose search over q6 has a
# pair of branches that lives only between two samples (0.02 rad of a 0.026 rad step; two roots of SP6's quartic turn
# real and back), with two solutions on it, 0.012 rad apart: both were missed (4 of 6 found). The search now
# watches how near SP6's complex roots are to turning real (_kernels._trig2m) and looks between samples where
# that margin peaks (search._islands), as it did for SP3's islands.
ISLAND6_H = np.array([[-0.4420184425651005 , -0.1276833224417144 , -0.8878719871707679 ],
       [ 0.16632190501815936, -0.8148684699538468 , -0.555271465669007  ],
       [-0.16632190501815936,  0.8148684699538468 ,  0.5552714656690071 ],
       [ 0.44240529976858867,  0.8905951058643652 ,  0.10544149158232444],
       [-0.22882540953803648, -0.753578866475139  ,  0.6162449382768141 ],
       [-0.35576973454420535, -0.9322487718884391 ,  0.06587961213336574]])
ISLAND6_P = np.array([[-0.5142017364482178  ,  0.24601911491713038 ,  0.8293594472202019  ],
       [ 0.8881615746757336  , -0.8350939599978549  , -0.860446136636012   ],
       [-0.4635247303412422  ,  1.395196795134762   , -0.4119869552284658  ],
       [-0.4705126250913372  , -0.5005245290425423  ,  0.3404117445223487  ],
       [ 1.4721488935562828  , -1.1486970485001848  ,  0.34650732872080064 ],
       [-0.5071927825047288  ,  0.7794555599181064  , -0.8656450477521781  ],
       [-0.06975210367310442 ,  0.21563804356994104 ,  0.009044930006615215]])
ISLAND6_R_NT = np.array([[-0.48640797132711094,  0.38013583274659657,  0.7867045405306211 ],
       [ 0.7246356784975756 , -0.3275577866727161 ,  0.6063077022753621 ],
       [ 0.4881704813667067 ,  0.864987077968291  , -0.11613326857569656]])
ISLAND6_Q_GEN = np.array([-2.3286532057354714 , -0.29588174557049296,  0.31162750440280185,  2.1475155901101566 ,
        0.7064649788979764 ,  2.5341135076639585 ])

# Found 2026-12-05 by bench_coverage.py --dense-only --seed 2026: a '6R-two-parallel' arm whose search over q6 had
# two branches end between two samples, the residual of one dipping below 0 and back 0.0004 and 0.00007 rad before
# the end (two solutions, ik_all found none). The step was sampled finer, the last sub-sample fell 1e-5 rad before
# the end, and the samples towards the end started only as far again back from there. They now start at least one
# (sub-)step back (search._edge).
END2_H = np.array([[ 0.5850018375274371 ,  0.7866191468627535 , -0.1974921970064539 ],
       [-0.691055354994824  , -0.38356928109728555,  0.6126312944434764 ],
       [-0.691055354994824  , -0.38356928109728566,  0.6126312944434762 ],
       [ 0.1536809985705233 , -0.9849039516893864 ,  0.0796640234045319 ],
       [ 0.5835094536458288 , -0.538620279492332  ,  0.6077868968853709 ],
       [-0.7237358175991161 ,  0.6765866914086116 ,  0.1357826032041194 ]])
END2_P = np.array([[ 1.0593943911131904e+00, -8.4654098352180340e-01, -3.2860496557184277e-01],
       [-1.2928234413110498e+00,  1.1607759155157915e+00,  9.8318114916823562e-01],
       [-1.3355513609788483e-02, -2.1841939142671835e-01, -4.5212546494166395e-02],
       [-1.7084928803308497e-01, -7.3391485290840675e-01, -1.2676049675256809e+00],
       [ 2.4107878679090550e-01,  3.8470699865016128e-01, -6.8767138704455943e-02],
       [ 1.0114591073294690e+00, -5.6863478823563773e-01,  1.0137509871695205e+00],
       [ 2.8073623184999152e-01,  6.7233929209098431e-04, -2.6441030507924373e-01]])
END2_R_NT = np.array([[ 0.7381324670758096  , -0.3003486159836025  , -0.604111885270694   ],
       [-0.036308437981607114,  0.8764545611614141  , -0.4801136319150796  ],
       [ 0.6736780821578756  ,  0.37632181852250707 ,  0.6360343784136185  ]])
END2_Q_GEN = np.array([ 2.587421579294828  , -3.009494131998509  , -1.8912553124323839 , -0.44222638831898964,
        0.5239246367237946 ,  0.6655323823423309 ])

# Found 2026-12-05 by bench_coverage.py --dense-only --seed 99: a '6R-two-parallel' arm whose search over q6 has two
# branches that end and begin again 0.003 rad apart within one step; the step's branches paired up across the gap
# (0.47 rad apart, three times nearer than any other), so the solutions at its two ends were missed (4 of 6 found).
# A pair more than 0.25 rad apart (was 0.5) now sends the step to be sampled finer (search._ambiguous).
GAP_H = np.array([[-0.4793758463055681  , -0.47262383771432676 ,  0.739476508080549   ],
       [-0.07657175956924975 , -0.833997419088481   ,  0.5464293829857811  ],
       [ 0.07657175956924976 ,  0.833997419088481   , -0.5464293829857813  ],
       [-0.022166352626096498, -0.21571453437823807 , -0.9762048414493936  ],
       [-0.19586323096370994 ,  0.9681924962142389  ,  0.15569484587133095 ],
       [ 0.641887046323497   ,  0.6846843110263627  ,  0.3452367506457734  ]])
GAP_P = np.array([[-0.07904975188472387 , -0.26420805993809243 ,  0.4032098005008604  ],
       [-0.23255091309683068 ,  0.22809969671934174 ,  0.8375725735970616  ],
       [ 0.3249327157869123  ,  0.21727089589884596 , -2.091359112793087   ],
       [ 0.03777297136964316 ,  0.3343061631546165  ,  0.867542389432881   ],
       [-0.005800748381273917, -0.08040323317651937 , -0.042889016378162254],
       [ 0.5014424294680888  ,  0.03799141802046807 ,  0.6320439362787345  ],
       [-0.49753081817349215 , -0.0672294161014112  ,  0.24006706336709693 ]])
GAP_R_NT = np.array([[-0.1608917777374552 ,  0.33138145500320015,  0.9296774532796004 ],
       [-0.2623441804592888 , -0.9224226468174818 ,  0.2833937042655937 ],
       [ 0.9514669551989835 , -0.19829975269322148,  0.23534621570397474]])
GAP_Q_GEN = np.array([-0.8708785393152461 , -0.06257454764479808,  0.8549819818059832 , -2.8298929762372493 ,
        0.3531147093963769 , -2.796005318994768  ])

# Found 2026-12-05 by bench_coverage.py --dense-only --seed 99: a '6R-spherical-middle' arm whose search over q6 has
# a pair of branches born between two samples with both roots of one of them 5e-5 and 1e-5 rad from the birth,
# between the last two samples towards it, where that branch's residual alone showed no extremum (4 solutions,
# none found). The residuals of the two branches at the last sample and at the fold are now read as one curve
# through the fold (search._fold_dip).
FOLD_H = np.array([[ 0.10910096590129875 , -0.32862982926363005 ,  0.9381361386054591  ],
       [-0.9431824819426702  ,  0.275246952477154   ,  0.18613414761538014 ],
       [-0.18055621846545175 ,  0.9834815944504893  ,  0.012783010231521815],
       [-0.27336417959758097 , -0.9573637789860528  , -0.09341637971194143 ],
       [-0.5903052430785158  ,  0.5699617092812078  , -0.571562218789222   ],
       [-0.2352807532628211  , -0.3823227693145864  , -0.8935727542890421  ]])
FOLD_P = np.array([[ 0.4262313717287658  ,  0.187480564223307   , -0.12617524308546044 ],
       [ 1.0384492894624953  , -0.26033501995033015 , -0.30491960401334284 ],
       [-0.3794170565831416  ,  0.1704655302018907  ,  0.07341024966288195 ],
       [ 0.027888960881602864, -0.00603678932447585 ,  0.004749823980087053],
       [-0.8107993224877738  ,  0.6006076510143697  , -0.11777125084103962 ],
       [ 0.17456424345295385 , -0.9190084567994788  ,  1.013228857321473   ],
       [-0.03193646445709608 ,  0.3653529475124951  ,  0.9107068288093405  ]])
FOLD_R_NT = np.array([[ 0.5406060405485538 , -0.5210176951815662 , -0.6605192428916097 ],
       [-0.6974551941223124 ,  0.16146633504775204, -0.6982011707509919 ],
       [ 0.4704267861359766 ,  0.8381343471985485 , -0.27609682166196714]])
FOLD_Q_GEN = np.array([ 3.0765708757433057  ,  0.023688460246013676, -1.1733045045906214  , -1.631679316919623   ,
        0.20631255407039006 , -1.0304603349865138  ])

# Found 2026-12-05 by bench_coverage.py --dense-only --seed 31: a '6R-two-intersecting' arm whose search over q1 has
# two roots 0.0011 rad apart just before four branches end, on a branch whose other joints swing by 1.6 rad within
# 0.0025 rad of q1 there: 5 solutions found, the sixth missed. The odd count told that one was missing, but the twin
# step (Newton from each solution found) could not reach it: it is 4 rad away in the other joints. A count still odd
# after the twin step now sends the search again at twice the samples, and what it finds is merged in
# (solvers_check._merged).
FAR_TWIN_H = np.array([[-0.6921110712752172  ,  0.5921709829849562  ,  0.41269333884726317 ],
       [ 0.9972007405561042  ,  0.007286151006849445, -0.0744150188998356  ],
       [ 0.6864099256780195  , -0.3375922660669913  , -0.6441062612818241  ],
       [ 0.40411426401291956 , -0.4031524663871698  ,  0.8210723174405761  ],
       [ 0.14430918624717162 ,  0.9873559720593107  ,  0.0655975853480355  ],
       [ 0.32406300750770434 , -0.6960025523779     , -0.6407523813834095  ]])
FAR_TWIN_P = np.array([[-0.6737709303375465   , -0.2831848324050712   ,  1.307943517622658    ],
       [ 0.3731036615107593   ,  0.38410577887169095  , -1.054521452836996    ],
       [-0.5149346022144967   ,  0.16080823471184802  ,  0.06566561082867767  ],
       [ 0.8644255036729563   , -0.24925520317116728  , -1.398767964680365    ],
       [-0.4422344880288015   , -0.07531003579853562  ,  0.8280250964459783   ],
       [ 0.09425901942420628  ,  0.25656689979867714  , -0.062205878112311375 ],
       [-0.46608858287420557  , -0.026103301887435038 ,  0.0063663026897337605]])
FAR_TWIN_R_NT = np.array([[ 0.663534011017526  , -0.7102367232019007 ,  0.2351306301578345 ],
       [ 0.25343445802596176, -0.08232009897102217, -0.9638435437302507 ],
       [ 0.7039130569239929 ,  0.6991331763840332 ,  0.12537627355720649]])
FAR_TWIN_Q_GEN = np.array([-2.7200810400014    ,  2.6191393608993208 ,  0.8068383993319523 , -3.0491951414057197 ,
        0.8154291891874954 ,  0.01206126523083828])

# Found 2026-12-05 by bench_coverage.py --dense-only --seed 41: a '6R-two-parallel' arm whose residual over q6 is
# S-shaped about a sample: a root 0.008 rad before it (a sign change, found), then the residual flat across the next
# step with a dip through 0 inside it, two roots 0.022 rad apart; the samples rise monotonically through it, so no
# extremum showed (2 of 4 found). The cubic through four samples now shows such a dip (search._wiggle).
WIGGLE_H = np.array([[ 0.3870653185825919 , -0.7715596159380268 ,  0.5048526499921747 ],
       [-0.21907499128887986, -0.9169338773800885 ,  0.33352423106049467],
       [-0.2190749912888798 , -0.9169338773800885 ,  0.33352423106049467],
       [-0.6899679710109924 ,  0.7184378794292001 ,  0.08826784454289605],
       [-0.7405301626692598 , -0.5904140427608232 , -0.32097715851421676],
       [-0.10369969470678911, -0.953405992812535  ,  0.28330793526984616]])
WIGGLE_P = np.array([[-0.7292135263420625  , -0.05687466867277006 ,  0.18711053695183844 ],
       [ 0.7810102390377376  ,  0.29437383527351274 ,  0.04092780467596707 ],
       [ 0.04275495783123648 ,  0.08140542177752222 ,  0.39536016717801375 ],
       [-0.019673064208786617, -0.24829572957079463 , -1.144702626987356   ],
       [-0.36006909602147574 , -0.5752174400341009  ,  0.6338351880606533  ],
       [ 0.5008863549592697  ,  0.6847146557681427  , -0.41543285168438165 ],
       [-0.40841374492070587 , -0.09424286652705485 , -0.038078488685961476]])
WIGGLE_R_NT = np.array([[ 0.956901296024454  ,  0.28849563720021243, -0.03331931846786791],
       [ 0.15001918257909427, -0.5892810760192123 , -0.7938778610743229 ],
       [-0.24866474322875023,  0.7546642172264987 , -0.6071637050358801 ]])
WIGGLE_Q_GEN = np.array([-1.10165996558562   ,  1.8489622981786695 ,  0.13943442259953764, -1.8732785301064114 ,
       -2.0164103495284573 , -1.756648142886104  ])

# Found 2026-12-05 by bench_coverage.py --dense-only --seed 41: a '6R-two-intersecting' arm whose search over q1 has
# two islands of SP6 (a pair of branches living between samples) with a sample in the 0.003 rad gap between them
# and none on either: the island search found the first (no root on it) and never looked at the second, which
# holds two solutions (2 of 4 found). Where it finds one island, it now looks in the other step beside that sample
# too (search._islands).
ISLANDS2_H = np.array([[ 0.9348806653994391 ,  0.29775150163365655,  0.19324126044197903],
       [ 0.14032434276495778,  0.2677420169962637 ,  0.9532173367927983 ],
       [ 0.05087190271596026,  0.13516477585502573, -0.9895163125902062 ],
       [ 0.16978571619728897,  0.04807660318916331, -0.9843075996867876 ],
       [-0.5269688406942123 , -0.7079565862738676 ,  0.47021411387669965],
       [ 0.6201281289443408 , -0.44841664302322576, -0.6437108185759908 ]])
ISLANDS2_P = np.array([[ 0.5853236146839311   ,  0.3546233300249294   , -0.3061727210326463   ],
       [-0.26454921086505345  , -0.6785126816541137   ,  1.3025559482100961   ],
       [ 0.6783937984537574   ,  1.9896243547094468   , -2.0203022110824453   ],
       [-0.8759534750400207   , -1.4514424471626814   ,  1.5289624469471863   ],
       [ 0.2828247762430215   ,  0.1054890769339773   , -0.6811030181888763   ],
       [-0.01570740319847236  , -0.27439607791157294  , -0.0038460538601400585],
       [-0.02218751807574515  ,  0.14216308808163697  , -0.22800520151845652  ]])
ISLANDS2_R_NT = np.array([[-0.6560633204952775 ,  0.515347815716016  , -0.5513597268004276 ],
       [-0.6893899521743742 , -0.11192430187091826,  0.7156915847568153 ],
       [ 0.3071195424288805 ,  0.8496408532359061 ,  0.42870503515918296]])
ISLANDS2_Q_GEN = np.array([ 2.6567840852426343, -1.8076643903871685, -2.442834614710094 , -0.2780648981779854,
       -3.1154779562573642,  1.0707802342564472])

# Found 2026-12-05 by bench_coverage.py --dense-only --seed 73: a '6R-two-intersecting' arm whose search over q1 has
# an island of SP6 (found) with two roots 0.00013 rad apart inside it, under a dip of one branch's residual between
# two of the island's samples, which only had their sign changes looked at (4 of 6 found). The island's samples now
# have their dips searched too, as at a seam (search._islands, search._seam).
ISLAND_DIP_H = np.array([[ 0.14737228203651306 ,  0.18243847439368324 , -0.9721098773020753  ],
       [ 0.017345997927802198,  0.3959511354205173  , -0.9181077358976407  ],
       [-0.8198133539095815  , -0.06469666319529183 , -0.5689643279880717  ],
       [ 0.6830247523675321  ,  0.4642393946428525  ,  0.563878508293151   ],
       [-0.9221281852353646  ,  0.23569263928729692 , -0.30680382947466833 ],
       [ 0.7572224407538996  , -0.20709167364515582 , -0.6194571929726505  ]])
ISLAND_DIP_P = np.array([[ 0.211097867117996   , -1.0120936724271834  ,  0.6384482554423051  ],
       [-0.8812003698809077  ,  0.9950618090992582  , -1.0217216452391353  ],
       [ 1.0340962733545207  , -0.03995171098913636 , -0.666664862632338   ],
       [-0.8796285255849535  , -0.15978562101571295 ,  0.4371412049851673  ],
       [ 0.9955589492621633  ,  0.8189608138007435  ,  0.8608491351041269  ],
       [ 0.061530712914749985, -0.014566404095653573,  0.09512041133624133 ],
       [ 0.1833728052827177  ,  0.11017438167541083 ,  0.1703554300341768  ]])
ISLAND_DIP_R_NT = np.array([[-0.3977536610126339 ,  0.2626978516448617 ,  0.8790801237044441 ],
       [ 0.28424400501531905,  0.946275728723019  , -0.15416741173986717],
       [-0.8723516325220567 ,  0.18855260266273935, -0.4510549248874343 ]])
ISLAND_DIP_Q_GEN = np.array([ 0.5013516890599603 , -0.13249913347139808,  0.1860885404355237 , -2.0080845711710436 ,
        1.0356920201183701 ,
        1.168197564231411  ])

# Found 2026-12-05 by bench_coverage.py --dense-only --seed 83: a '6R-two-intersecting' arm whose search over q1 found
# 3 of 4 solutions. The fourth lies where a branch is born and its other joints swing 1.2 rad within 0.0026 rad of
# q1: neither the twin step nor the second search (twice the samples) found it. The second search had it as a
# candidate with q1 right and the other joints 0.05-0.35 rad off, which failed the check and was dropped; its failing
# candidates now get Newton steps on the whole chain (solvers_check._promote).
STEEP_H = np.array([[0.9463923224256089, -0.25884218831728245, 0.1932415421201737],
                    [0.2788041795786866, -0.6727000955660535, -0.685377859924639],
                    [-0.5333249858393085, -0.7724165419530135, 0.34487265069420914],
                    [-0.39640701454015514, -0.18622132743166847, -0.8989900422323646],
                    [0.7936663811012575, -0.5877310898933364, 0.15705362613586557],
                    [-0.6786382135412697, 0.2328753700727424, 0.6965767991650291]])
STEEP_P = np.array([[0.28516362119014504, -0.8095754790171609, 0.35139572471116903],
                    [-0.38538696054875204, 0.9839422970268654, -0.2958599426686158],
                    [1.1283780534893637, -0.7604693898719099, 0.6668048297331195],
                    [-0.12974669151454976, 0.31904858510247214, -0.4830885404781384],
                    [-0.2292613772135419, -0.07267982586912503, -1.0097979128848784],
                    [0.0645095177998638, -0.1117437314231271, 0.2098657244295583],
                    [-0.12734476321041632, -0.06669301021490304, -0.11047099087666967]])
STEEP_R_NT = np.array([[0.4688551624022152, 0.6677042939239513, -0.5782264371025508],
                       [0.4080244253386642, 0.4168793136034918, 0.812236237936066],
                       [0.7833842639572512, -0.6167516629608699, -0.07698364254278961]])
STEEP_Q_GEN = np.array([1.4811962686924565, -1.9105348339579153, 1.165465532166528, 0.9048737307060506,
                        -0.131108208581467, -2.0020173433133146])

# Found 2026-12-06 by bench_coverage.py --dense-only --seed=139: a '6R-two-parallel' arm and target with 4 solutions,
# of which the search found 2 and a failing candidate that Python's polish made a third, after the odd-count steps
# had looked at an even count. Failing candidates are now brought onto the target by Newton steps before the count
# is looked at (solvers_check._promote), and only the search with four times the samples finds the fourth: an odd
# count now sends the search again with 2N samples, then with 4N (solvers_check.RETRIES).
ODD4_H = np.array([[-0.05118597555581894, 0.9241513143164127, -0.37858201773677286],
                   [-0.38344424118134035, -0.34272318850314143, 0.8576195718190591],
                   [0.38344424118134035, 0.34272318850314143, -0.8576195718190591],
                   [-0.1842940520448335, 0.2208302837106736, -0.957741973694982],
                   [-0.32564009191389065, -0.34610823361062387, -0.8798679566646616],
                   [0.5370771345100955, 0.490440818697914, -0.6863060213500568]])
ODD4_P = np.array([[0.5594798553184283, 0.6057838993630226, -0.019908142314204087],
                   [-0.4921749306885736, -0.23037889571576986, 0.4323519600364101],
                   [0.33315947372711774, 0.18629644350293817, -1.2318857690142198],
                   [-0.2829625642006187, -0.1760486095864483, 0.0664665088890738],
                   [1.0956755534973543, -0.6124345200789041, -0.2238303813704403],
                   [-1.0613783773632883, 0.3460805355297586, 0.9630921226802587],
                   [-0.7623319968130223, -0.01985282750492294, -0.2906477462827248]])
ODD4_R_NT = np.array([[-0.7688731794832013, -0.2043945746466534, -0.6058522028732797],
                      [0.49241774846328223, -0.7937077741584891, -0.3571452508976262],
                      [-0.40787105176727523, -0.5729317822353637, 0.7109081361433881]])
ODD4_Q_GEN = np.array([2.2357909234308124, 1.9650642988491, 2.268046140720168, -2.142388991900031,
                       1.0015282236294825, 1.7465395378298831])

# Found 2026-12-06 by bench_coverage.py --dense-only --seed=193: a '6R-two-intersecting' arm whose search over q1 found
# 2 of 6 solutions. The other 4 lie on two islands of SP5, 0.01 rad wide, between samples. The margin of SP5 is near
# -1 away from an island and rises to 0 within a few thousandths of a radian of it; at the samples about the first
# it reads -0.99, -0.77, -0.89, a peak no parabola through them brings near 0, so the island was never searched. A
# margin peak above search.STEEP (-0.9) is now searched too.
STEEP_ISLAND_H = np.array([[0.3775176963214992, -0.9001004375065711, -0.21748469225347267],
                           [-0.9472267936170474, -0.2777415370979752, 0.16006573657226483],
                           [0.4058778105142001, 0.9114053564743547, 0.06784894341147465],
                           [-0.3724361686728109, -0.8606081812041644, -0.3473396877824039],
                           [-0.9077736256025436, -0.4016921923339375, -0.1207908410367614],
                           [0.06176674391013218, 0.84902885846035, -0.5247236099588575]])
STEEP_ISLAND_P = np.array([[0.20462370854890227, -0.26940755708673586, -0.16076761142550028],
                           [-0.17890627660157604, 0.1819542146136438, -0.2181387224435143],
                           [-0.198025934622673, 0.01801162957347946, 1.1347930649829174],
                           [0.4031067162221219, -0.9246702041426285, -1.2061499349742557],
                           [0.48478558069265576, 1.1444648853642778, 0.4905657439205112],
                           [-0.0008732127688303448, -0.11648701292945904, 0.07518523114665591],
                           [-0.521225864315505, 0.016801471164900758, -0.5637159715582039]])
STEEP_ISLAND_R_NT = np.array([[-0.6696434563243293, -0.3286965324266423, -0.665985158222544],
                              [0.6714152806236305, 0.11537270907769691, -0.7320455306503575],
                              [0.3174573394128673, -0.9373621112306456, 0.1434332948869579]])
STEEP_ISLAND_Q_GEN = np.array([0.29999050355269175, 2.5703803102680514, 1.7455985786279866, -1.6481163570468647,
                               -2.107317569683753, 0.8623831364827437])

# Found 2026-12-06 by bench_coverage.py --dense-only --seed=263: a '6R-two-intersecting' arm whose search over q1 found
# 2 of 4 solutions. The other 2 lie on an island of SP5 0.004 rad wide, between samples whose margins read -0.996,
# -0.966, -0.972: below search.STEEP, and no parabola through them comes near 0. Near an island the margin rises like
# -1 + A / ((x - x0)^2 + e), so 1 / (1 + margin) is a parabola: through those samples it dips to 0.55, below the
# island's level 1 (search._sharp_peak).
SHARP_ISLAND_H = np.array([[-0.27339486445775635, -0.12496234609712506, 0.9537503133137244],
                           [-0.5788919387024997, 0.6494794012719104, 0.4930117956284029],
                           [0.7625186345431729, 0.6350342191837595, 0.12368052571075328],
                           [-0.8241458690591753, -0.5663648189844406, -0.0038050400022540073],
                           [-0.5658659667869345, 0.20672337190270954, -0.7981611085122239],
                           [0.11068927070989548, -0.8181315631635201, 0.5642770868158007]])
SHARP_ISLAND_P = np.array([[-0.23994518824013839, -0.27879766908793713, 0.2657057327155521],
                           [0.24510554433659143, 1.3478456373131245, 0.09930441054177569],
                           [-0.9104203761791756, 0.3241890772808118, 0.12857993787855632],
                           [1.0330007882313628, -1.4272536596155998, -1.0027870476127017],
                           [-0.20473533337020966, -0.01386113009233575, -0.17856919978066588],
                           [0.14928810240853285, -0.22971760187786444, 0.30251014550063277],
                           [0.07283960558851438, 0.312205853342702, 0.3397420237747471]])
SHARP_ISLAND_R_NT = np.array([[-0.09845632063117715, -0.6137186812557441, 0.783361815003438],
                              [-0.9902370904289435, 0.13847552954332518, -0.01596973564326812],
                              [-0.09867551705763175, -0.7772862458550299, -0.6213607924048664]])
SHARP_ISLAND_Q_GEN = np.array([2.5800846578624648, 1.3117223506780264, -1.0557418028986103, 0.7909555386225613,
                               -2.3501498866230874, 2.7196926833765342])

# Found 2026-12-06 by bench_coverage.py --dense-only --seed=271: a '6R-general' arm whose 2-D search (100 x 100 grid)
# found none of the target's 4 solutions and answered "out of reach". The (q3, q4, q5) problem had solutions at only
# 7 of the grid's 10,000 points: it is solvable only in bands of (q1, q2) narrower than a grid step, and no point
# beside a solution lay in one. Where no solution is found and that problem is solvable at fewer than one point in
# search2d.THIN, a grid twice as fine is searched too (and four times as fine while the count is odd).
THIN2D_H = np.array([[0.5750243610163802, -0.20126445615907168, -0.7929940749619109],
                     [0.568398998836749, -0.5625205952442487, 0.6004108243922969],
                     [0.20099830024068105, -0.15560267091082366, 0.9671543269332847],
                     [-0.19766615180663633, 0.32539334831325534, 0.9246876560782264],
                     [0.27705012283762664, 0.7244205660051752, -0.6312353546692374],
                     [-0.40456726235011364, 0.7730936536113787, 0.48851973653102676]])
THIN2D_P = np.array([[0.6031279843958832, -1.1429714754661244, -0.12525425529441322],
                     [-0.5040009436364065, 0.08111995103771608, 0.07082775101257532],
                     [-1.2184724407790979, 0.6463125477122522, 0.5349310467656158],
                     [1.6913522311346365, -0.05714041164477013, -1.0024629072395441],
                     [-1.0463938846530665, 0.4944322653114087, 0.4214937942942041],
                     [0.15167124529225073, 0.39257216214137847, -0.34068512513565674],
                     [-0.12025813161485677, 0.560722499425785, -0.23275887049516153]])
THIN2D_R_NT = np.array([[-0.5881192748181897, 0.3143683809774159, 0.7451766499488324],
                        [-0.42905866144924554, 0.6597512151168075, -0.6169578585181318],
                        [-0.6855832433940523, -0.6825693043153457, -0.2531299294507795]])
THIN2D_Q_GEN = np.array([-0.5604803666214367, -1.467540734841376, -2.481277027032133, 2.9633117124093404,
                         -1.2965003195903706, 2.842172186499658])

# Found 2026-12-06 by bench_coverage.py --dense-only --seed=379: a '6R-two-parallel' arm whose search gave 7 of the
# target's 8 solutions (the odd count's finer searches did not find the eighth either). The missed root lies 1.5e-4
# rad from where two branches of SP6 are born; one of them swings 1 rad (q4) within 7e-4 rad of its birth, so its
# own trace towards the birth stopped a sample early, and the other's showed no sign change. The partner's residual
# at the last sample, of the other sign than at the birth, is now followed to the root (search._fold_root).
SWING_H = np.array([[0.24745491112385992, -0.9443295979770476, 0.21681253964010072],
                    [-0.060250817661031957, 0.5679947047554431, 0.8208238875306653],
                    [-0.06025081766103196, 0.5679947047554432, 0.8208238875306652],
                    [-0.19081281779729625, 0.8338744913726768, -0.517922582247787],
                    [0.827131307865135, -0.19928935788434368, 0.5254879174475444],
                    [-0.26599560595172056, 0.6768805622555125, -0.686351981169311]])
SWING_P = np.array([[0.03979562871750393, 0.32032589601268074, 0.08245896342032649],
                    [-0.011028677780803721, -0.7107904187134269, 0.9653302375049888],
                    [0.02968191185481444, 0.13912327959616572, -1.60927783693573],
                    [0.6413660881069728, 0.7915996807866715, -0.06292092093967516],
                    [-1.2247203227381545, -0.15003534746523517, -0.5542712026400868],
                    [-0.010390047641234856, -1.4409305630978326, 1.1769970742232116],
                    [0.04171109831147124, -0.22833236478676233, 0.08036843391874784]])
SWING_R_NT = np.array([[-0.8298881175327824, -0.3584065428852791, 0.42758678931290417],
                       [-0.5230280758213701, 0.232955230727075, -0.8198618739638336],
                       [0.19423528073058757, -0.9040335228817107, -0.38078346238458466]])
SWING_Q_GEN = np.array([-2.1110198813155403, -2.2936995646989766, -1.8719727609610448, -1.1833078263459778,
                        1.1019310011970553, 1.9550693492373998])

CASES = {   # name: (H, P, R_nT, the missed solution, the solver, even count, the dense search's seed)
    "island": (ISLAND_H, ISLAND_P, ISLAND_R_NT, ISLAND_Q_GEN, G.spherical_middle, False, 11),
    "twin2d": (TWIN2D_H, TWIN2D_P, TWIN2D_R_NT, TWIN2D_Q_GEN, gen_six_dof, True, 13),
    "odd": (ODD_H, ODD_P, ODD_R_NT, ODD_Q_GEN, G.two_intersecting, True, 17),
    "island6": (ISLAND6_H, ISLAND6_P, ISLAND6_R_NT, ISLAND6_Q_GEN, G.two_parallel, True, 19),
    "end2": (END2_H, END2_P, END2_R_NT, END2_Q_GEN, G.two_parallel, True, 23),
    "gap": (GAP_H, GAP_P, GAP_R_NT, GAP_Q_GEN, G.two_parallel, True, 29),
    "fold": (FOLD_H, FOLD_P, FOLD_R_NT, FOLD_Q_GEN, G.spherical_middle, False, 31),
    "far_twin": (FAR_TWIN_H, FAR_TWIN_P, FAR_TWIN_R_NT, FAR_TWIN_Q_GEN, G.two_intersecting, True, 37),
    "wiggle": (WIGGLE_H, WIGGLE_P, WIGGLE_R_NT, WIGGLE_Q_GEN, G.two_parallel, True, 41),
    "islands2": (ISLANDS2_H, ISLANDS2_P, ISLANDS2_R_NT, ISLANDS2_Q_GEN, G.two_intersecting, True, 43),
    "island_dip": (ISLAND_DIP_H, ISLAND_DIP_P, ISLAND_DIP_R_NT, ISLAND_DIP_Q_GEN, G.two_intersecting, True, 47),
    "steep": (STEEP_H, STEEP_P, STEEP_R_NT, STEEP_Q_GEN, G.two_intersecting, True, 53),
    "odd4": (ODD4_H, ODD4_P, ODD4_R_NT, ODD4_Q_GEN, G.two_parallel, True, 59),
    "steep_island": (STEEP_ISLAND_H, STEEP_ISLAND_P, STEEP_ISLAND_R_NT, STEEP_ISLAND_Q_GEN, G.two_intersecting, True,
                     61),
    "sharp_island": (SHARP_ISLAND_H, SHARP_ISLAND_P, SHARP_ISLAND_R_NT, SHARP_ISLAND_Q_GEN, G.two_intersecting, True,
                     67),
    "thin2d": (THIN2D_H, THIN2D_P, THIN2D_R_NT, THIN2D_Q_GEN, gen_six_dof, True, 71),
    "swing": (SWING_H, SWING_P, SWING_R_NT, SWING_Q_GEN, G.two_parallel, True, 73),
}


def _wrap(a):
    return (np.asarray(a) + math.pi) % (2 * math.pi) - math.pi


def _case(name):
    H, P, R_nT, q_gen, solver, even, seed = CASES[name]
    form = POE(H, P, R_nT, np.zeros(6, dtype=bool))
    R, p = form.fk(q_gen)
    return form, R, p, q_gen, solver, even, seed


@pytest.mark.parametrize("jit", [True, False], ids=["compiled", "plain"])
@pytest.mark.parametrize("name", ["island", "odd", "island6", "end2", "gap", "fold", "far_twin",
                                  "wiggle", "islands2", "island_dip", "steep", "odd4",
                                  "steep_island", "sharp_island", "swing"])
def test_the_missed_solution_is_found(name, jit):
    _check_solver(name, jit)


@pytest.mark.parametrize("name", ["twin2d", "thin2d"])
def test_the_missed_solution_is_found_2d(name):
    _check_solver(name, None)   # the plain 2-D search takes seconds: the compiled one only


def _check_solver(name, jit):
    form, R, p, q_gen, solver, even, _ = _case(name)
    q = np.asarray(solver(form, R, p, jit=jit).q)
    assert len(q) >= 1, "the search found nothing"
    for x in q:                                           # every solution passes FK (the test's own POE.fk)
        Rq, pq = form.fk(x)
        assert np.abs(pq - p).max() < 1e-9 and np.abs(Rq - R).max() < 1e-9
    assert np.abs(_wrap(q - q_gen)).max(axis=1).min() < 1e-7   # the generating configuration is found
    if even:
        assert len(q) % 2 == 0


@pytest.mark.parametrize("name", sorted(CASES))
def test_against_a_dense_search(name):
    """Every distinct solution Levenberg-Marquardt reaches from 300 random starts is among ``ik_all``'s."""
    form, R, p, _, _, _, seed = _case(name)
    assert ik_all_misses(form, R, p, seed) == []


@pytest.mark.parametrize("jit", [True, False], ids=["compiled", "plain"])
def test_two_folds_in_one_step_of_the_two_parallel_search(jit):
    """The solution beside the two folds (FOLDS_H) is found, every solution passes FK, and they come in pairs."""
    form = POE(FOLDS_H, FOLDS_P, FOLDS_R_NT, np.zeros(6, dtype=bool))
    R, p = form.fk(FOLDS_Q_GEN)
    q = np.asarray(G.two_parallel(form, R, p, jit=jit).q)
    for x in q:
        Rq, pq = form.fk(x)
        assert np.abs(pq - p).max() < 1e-9 and np.abs(Rq - R).max() < 1e-9
    assert np.abs(_wrap(q - FOLDS_Q_GEN)).max(axis=1).min() < 1e-7
    assert len(q) % 2 == 0
