#include "render/frame_plan.h"

#include <algorithm>
#include <array>
#include <set>
#include <sstream>

namespace rtgi {

PassDecl& PassDecl::output(std::string name, const gl::Texture* tex, Check check) {
    return output(std::move(name), TextureFn([tex] { return tex; }), check);
}
PassDecl& PassDecl::output(std::string name, TextureFn tex, Check check) {
    outputs_.push_back({std::move(name), std::move(tex), check});
    return *this;
}
PassDecl& PassDecl::debugImage(std::string name, const gl::Texture* tex, float scale) {
    std::string n = name;
    return debugImage(std::move(name), [n, tex, scale] { return DebugImage{n, tex, scale}; });
}
PassDecl& PassDecl::debugImage(std::string name, std::function<DebugImage()> make) {
    debug_.push_back({std::move(name), std::move(make)});
    return *this;
}
bool PassDecl::uses(Resource r, Access a) const {
    return std::any_of(uses_.begin(), uses_.end(), [&](const Use& u) { return u.resource == r && u.access == a; });
}

bool FrameContext::has(Resource r) const { return plan && plan->writtenBefore(passIndex, r); }
bool FrameContext::accumulates(Resource r) const { return has(r); }

namespace {

std::string nameOf(Resource r) { return resourceDesc(r).name; }

struct Candidate {
    std::size_t order;
    std::unique_ptr<Pass> pass;
    PassDecl decl;
};

// A kept pass reads r (this frame or the previous one) — what keeps an onlyIfRead producer.
bool readByOthers(const std::vector<Candidate>& kept, const Candidate& self, Resource r) {
    for (auto& c : kept)
        if (&c != &self &&
            (c.decl.uses(r, PassDecl::Access::read) || c.decl.uses(r, PassDecl::Access::readPrevious)))
            return true;
    return false;
}

}  // namespace

FramePlan FramePlan::build(std::vector<std::unique_ptr<Pass>> script, const std::vector<Family>& families,
                           const Scene& scene, const Settings& settings) {
    std::set<std::string> forcedOff;
    {
        std::stringstream ss(settings.post.passesOff);
        std::string n;
        while (std::getline(ss, n, ','))
            if (!n.empty()) forcedOff.insert(n);
    }
    std::vector<Need> familyNeed;
    for (auto& f : families) {
        familyNeed.push_back(f.runs(scene, settings));
        if (familyNeed.back().needed && f.validate) f.validate(scene, settings);
    }

    std::vector<std::pair<std::size_t, SkippedPass>> skipped;
    std::vector<Candidate> kept;
    std::set<std::string> knownNames;
    for (std::size_t i = 0; i < script.size(); ++i) {
        std::string n = script[i]->name();
        knownNames.insert(n);
        if (forcedOff.count(n)) {
            skipped.push_back({i, {n, "forced off by passes.off"}});
            continue;
        }
        std::string familyWhy;
        for (std::size_t f = 0; f < families.size(); ++f)
            if (n.rfind(families[f].prefix, 0) == 0 && !familyNeed[f].needed) familyWhy = familyNeed[f].reason;
        if (!familyWhy.empty()) {
            skipped.push_back({i, {n, familyWhy}});
            continue;
        }
        PassDecl d;
        script[i]->declare(d, scene, settings);
        if (d.skipped()) {
            skipped.push_back({i, {n, d.skipReason()}});
            continue;
        }
        kept.push_back({i, std::move(script[i]), std::move(d)});
    }
    for (auto& n : forcedOff)
        if (!knownNames.count(n)) throw ConfigError("setting 'passes.off': there is no pass named '" + n + "'");

    // Drop producers nobody reads (post.history without a reprojecting pass,
    // brdf_lut without SSR or LPV specular); repeat, since a dropped pass
    // no longer keeps its own producers.
    for (bool changed = true; changed;) {
        changed = false;
        for (std::size_t k = 0; k < kept.size(); ++k) {
            const Candidate& c = kept[k];
            if (!c.decl.isOnlyIfRead()) continue;
            bool read = false;
            std::string outs;
            for (auto& u : c.decl.uses())
                if (u.access == PassDecl::Access::write || u.access == PassDecl::Access::accumulate) {
                    read |= readByOthers(kept, c, u.resource);
                    outs += (outs.empty() ? "" : ", ") + nameOf(u.resource);
                }
            if (read) continue;
            skipped.push_back({c.order, {c.pass->name(), "no pass in this frame reads " + outs}});
            kept.erase(kept.begin() + std::ptrdiff_t(k));
            changed = true;
            break;
        }
    }

    FramePlan plan;
    std::bitset<R::count> written;
    std::vector<std::string> writer(R::count);
    for (auto& c : kept)
        for (auto& u : c.decl.uses())
            if (u.access == PassDecl::Access::write || u.access == PassDecl::Access::accumulate)
                plan.all_.set(std::size_t(u.resource.index));
    for (auto& c : kept) {
        const std::string n = c.pass->name();
        for (auto& u : c.decl.uses()) {
            const std::size_t r = std::size_t(u.resource.index);
            switch (u.access) {
                case PassDecl::Access::read:
                    if (!written[r])
                        throw ConfigError("frame build: pass '" + n + "' reads '" + nameOf(u.resource) +
                                          "', which no earlier pass in this frame writes (its producer is later, "
                                          "skipped or forced off by passes.off)");
                    break;
                case PassDecl::Access::readPrevious:
                    if (!plan.all_[r])
                        throw ConfigError("frame build: pass '" + n + "' reads the previous frame's '" +
                                          nameOf(u.resource) + "', which no pass in this frame writes");
                    break;
                case PassDecl::Access::write:
                    if (written[r])
                        throw ConfigError("frame build: pass '" + n + "' writes '" + nameOf(u.resource) +
                                          "', which '" + writer[r] +
                                          "' already wrote this frame (declare accumulate to add to it)");
                    break;
                default: break;
            }
        }
        plan.before_.push_back(written);
        for (auto& u : c.decl.uses())
            if (u.access == PassDecl::Access::write || u.access == PassDecl::Access::accumulate) {
                written.set(std::size_t(u.resource.index));
                if (writer[std::size_t(u.resource.index)].empty()) writer[std::size_t(u.resource.index)] = n;
            }
        plan.passes_.push_back(std::move(c.pass));
        plan.decls_.push_back(std::move(c.decl));
    }
    std::sort(skipped.begin(), skipped.end(), [](auto& a, auto& b) { return a.first < b.first; });
    for (auto& s : skipped) plan.skipped_.push_back(std::move(s.second));

    // A technique the user asked for explicitly must run, or say why not.
    for (std::size_t f = 0; f < families.size(); ++f) {
        const Family& fam = families[f];
        if (!fam.requested || !fam.requested(settings)) continue;
        bool runs = std::any_of(plan.passes_.begin(), plan.passes_.end(),
                                [&](auto& p) { return p->name().rfind(fam.prefix, 0) == 0; });
        if (runs) continue;
        std::string why = familyNeed[f].reason;
        for (auto& s : plan.skipped_)
            if (why.empty() && s.name.rfind(fam.prefix, 0) == 0) why = s.reason;
        throw ConfigError("setting '" + fam.key + "': requested, but " +
                          (why.empty() ? std::string("this build has no such passes") : why));
    }
    return plan;
}

std::string FramePlan::table() const {
    using A = PassDecl::Access;
    std::vector<std::array<std::string, 3>> rows{{"pass", "reads", "writes (+= adds to an earlier writer)"}};
    for (std::size_t i = 0; i < passes_.size(); ++i) {
        std::string reads, writes;
        auto add = [](std::string& s, const std::string& x) { s += (s.empty() ? "" : " ") + x; };
        for (auto& u : decls_[i].uses()) {
            std::string n = nameOf(u.resource);
            bool before = before_[i][std::size_t(u.resource.index)];
            switch (u.access) {
                case A::read: add(reads, n); break;
                case A::readIfWritten: if (before) add(reads, n); break;
                case A::readPrevious: add(reads, n + "[previous frame]"); break;
                case A::write: add(writes, n); break;
                case A::accumulate: add(writes, before ? "+=" + n : n); break;
            }
        }
        rows.push_back({passes_[i]->name(), reads.empty() ? "-" : reads, writes.empty() ? "-" : writes});
    }
    std::size_t w0 = 0, w1 = 0;
    for (auto& s : skipped_) w0 = std::max(w0, s.name.size());
    for (auto& r : rows) {
        w0 = std::max(w0, r[0].size());
        w1 = std::max(w1, r[1].size());
    }
    std::ostringstream o;
    for (auto& r : rows)
        o << r[0] << std::string(w0 + 2 - r[0].size(), ' ') << r[1] << std::string(w1 + 2 - r[1].size(), ' ')
          << r[2] << "\n";
    o << "\nskipped:\n";
    for (auto& s : skipped_) o << "  " << s.name << std::string(w0 + 2 - s.name.size(), ' ') << s.reason << "\n";
    return o.str();
}

}  // namespace rtgi
